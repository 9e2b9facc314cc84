"""PLC Bridge: Home Assistant talks to PLCs through the network interfaces their vendors ship."""

from __future__ import annotations

from functools import partial

from homeassistant.config_entries import ConfigEntry
from homeassistant.core import HomeAssistant
from homeassistant.helpers import config_validation as cv
from homeassistant.helpers.typing import ConfigType

from .const import DOMAIN
from .coordinator import PlcBridgeConfigEntry, PlcCoordinator, PlcRuntimeData, link_error
from .entity import plc_device
from .model import migration
from .model.kinds import PLATFORMS
from .plc import PlcError
from .runtime.connection import create_polling_client
from .runtime.entities import PointEntities, async_register_devices
from .runtime.entry_title import async_follow_device_name
from .runtime.expose import async_start_exposes
from .runtime.issues import (
    CERTIFICATE_CHANGED,
    TIMES_IN_SECONDS,
    async_check_tls,
    async_clear_all,
    async_clear_issue,
    async_raise_issue,
)
from .runtime.restore import async_remove_values
from .services import async_setup_services

CONFIG_SCHEMA = cv.config_entry_only_config_schema(DOMAIN)


async def async_setup(hass: HomeAssistant, config: ConfigType) -> bool:
    """Register the actions, once for every PLC."""
    async_setup_services(hass)
    return True


async def async_migrate_entry(hass: HomeAssistant, entry: ConfigEntry) -> bool:
    """Migrate an entry of an older version (model/migration.py), raising the issue it asks."""
    return await migration.async_migrate_entry(
        hass, entry, partial(async_raise_issue, hass, entry, TIMES_IN_SECONDS)
    )


async def async_setup_entry(hass: HomeAssistant, entry: PlcBridgeConfigEntry) -> bool:
    """Connect to the PLC, poll it once (its first points where it is paced), add its entities."""
    async_check_tls(hass, entry)
    client = create_polling_client(hass, entry.data, entry.options)
    entry.async_on_unload(client.close)  # also when the setup below fails
    try:
        device = await client.connect()
    except PlcError as err:
        raise link_error(hass, entry, err, setup=True) from err
    async_clear_issue(hass, entry, CERTIFICATE_CHANGED)
    points = PointEntities(entry)
    coordinator = PlcCoordinator(hass, entry, client, points.configs)
    await coordinator.stored.async_load()
    entry.async_on_unload(coordinator.stored.async_save)  # after the entities are gone
    await coordinator.async_first_poll()
    settings = (dict(entry.data), dict(entry.options))
    entry.runtime_data = PlcRuntimeData(
        client=client, coordinator=coordinator, device=device, points=points, settings=settings
    )
    device_id = plc_device(hass, entry)
    async_register_devices(hass, entry, device_id, points.areas)
    async_follow_device_name(hass, entry, device_id)
    await hass.config_entries.async_forward_entry_setups(entry, PLATFORMS)
    async_start_exposes(hass, entry)
    entry.async_on_unload(entry.add_update_listener(async_update_entry))
    return True


async def async_update_entry(hass: HomeAssistant, entry: PlcBridgeConfigEntry) -> None:
    """Reload for a new connection or poll interval; follow edited devices and points in place."""
    runtime = entry.runtime_data
    if (dict(entry.data), dict(entry.options)) != runtime.settings:
        await hass.config_entries.async_reload(entry.entry_id)
        return
    await runtime.points.async_sync(hass, plc_device(hass, entry))


async def async_unload_entry(hass: HomeAssistant, entry: PlcBridgeConfigEntry) -> bool:
    """Remove the entities; the points' values are kept, the client logs out and closes."""
    return await hass.config_entries.async_unload_platforms(entry, PLATFORMS)


async def async_remove_entry(hass: HomeAssistant, entry: ConfigEntry) -> None:
    """Delete the issues and the kept values of a removed PLC."""
    async_clear_all(hass, entry)
    await async_remove_values(hass, entry.entry_id)
