"""The entry's title follows the name the user gives the PLC's device in Home Assistant.

Home Assistant's dialog after the config flow (and any later rename) sets the device's
`name_by_user`; the entry, and with it the pickers of machines and actions and the exported
file, then carry that name.
"""

from __future__ import annotations

from typing import Any

from homeassistant.config_entries import ConfigEntry
from homeassistant.core import Event, HomeAssistant, callback
from homeassistant.helpers import device_registry as dr


@callback
def async_follow_device_name(hass: HomeAssistant, entry: ConfigEntry[Any], device_id: str) -> None:
    """Title the entry as the user named the PLC's device, now and at each rename while loaded."""
    registry = dr.async_get(hass)

    @callback
    def follow() -> None:
        """Take the device's name given by the user, if there is one and it differs."""
        device = registry.async_get(device_id)
        if device is not None and device.name_by_user and device.name_by_user != entry.title:
            hass.config_entries.async_update_entry(entry, title=device.name_by_user)

    @callback
    def renamed(event_data: dr.EventDeviceRegistryUpdatedData) -> bool:
        """True for a change of the name the user gave the PLC's device."""
        return (
            event_data["action"] == "update"
            and event_data["device_id"] == device_id
            and "name_by_user" in event_data["changes"]
        )

    @callback
    def changed(event: Event[dr.EventDeviceRegistryUpdatedData]) -> None:
        """Follow a rename of the PLC's device."""
        follow()

    follow()  # a rename while the entry was not loaded
    entry.async_on_unload(
        hass.bus.async_listen(dr.EVENT_DEVICE_REGISTRY_UPDATED, changed, event_filter=renamed)
    )
