"""Config entry migrations: version 1 kept one point per subentry, version 2 devices of points."""

from __future__ import annotations

from types import MappingProxyType
from typing import Any

from homeassistant.config_entries import ConfigEntry, ConfigSubentry
from homeassistant.const import CONF_NAME
from homeassistant.core import HomeAssistant, callback
from homeassistant.helpers import device_registry as dr, entity_registry as er

from .const import CONF_POINTS, LOGGER, SUBENTRY_DEVICE, SUBENTRY_POINT


def migrated_name(plc: str) -> str:
    """Return the name of the machine that takes a version 1 PLC's points."""
    return f"{plc} points"


@callback
def async_migrate_points(hass: HomeAssistant, entry: ConfigEntry[Any]) -> None:
    """Move every version 1 point subentry into one machine, "<PLC> points".

    A point keeps its old subentry id as its point id, so its entity keeps its unique id, its
    entity id, its name and its history. The machine's name tells its device apart from the
    PLC's own (rename it afterwards). Entities are moved before the old subentries are removed,
    as removing a subentry removes what still belongs to it.
    """
    old = {
        subentry.subentry_id: subentry
        for subentry in entry.subentries.values()
        if subentry.subentry_type == SUBENTRY_POINT
    }
    if old:
        points = {
            sid: {CONF_NAME: subentry.title, **subentry.data} for sid, subentry in old.items()
        }
        device = ConfigSubentry(
            data=MappingProxyType({CONF_POINTS: points}),
            subentry_type=SUBENTRY_DEVICE,
            title=migrated_name(entry.title),
            unique_id=None,
        )
        hass.config_entries.async_add_subentry(entry, device)
        entities = er.async_get(hass)
        for entity in er.async_entries_for_config_entry(entities, entry.entry_id):
            if entity.config_subentry_id in old:
                entities.async_update_entity(
                    entity.entity_id, config_subentry_id=device.subentry_id, device_id=None
                )
        devices = dr.async_get(hass)
        for plc in dr.async_entries_for_config_entry(devices, entry.entry_id):
            # Since 2026.10 a device belongs to one subentry: the PLC's device may have been
            # moved to a point's; it belongs to none. (Before, it only loses the links.)
            if getattr(plc, "config_subentry_id", None) in old:
                devices.async_update_device(plc.id, new_config_subentry_id=None)
        for subentry_id in old:
            hass.config_entries.async_remove_subentry(entry, subentry_id)
        LOGGER.info("%s: %d points moved into the machine %s", entry.title, len(old), device.title)
    hass.config_entries.async_update_entry(entry, version=2)
