"""PLC Bridge: Home Assistant talks to PLCs through the network interfaces their vendors ship."""

from __future__ import annotations

from homeassistant.config_entries import ConfigEntry
from homeassistant.const import Platform
from homeassistant.core import HomeAssistant
from homeassistant.helpers import config_validation as cv
from homeassistant.helpers.typing import ConfigType

from .connection import create_client
from .const import CONF_TLS, DOMAIN
from .coordinator import PlcBridgeConfigEntry, PlcCoordinator, PlcRuntimeData, link_error
from .plc import PlcError, TlsMode
from .repairs import (
    CERTIFICATE_CHANGED,
    ISSUES,
    TLS_OFF,
    async_clear_issue,
    async_clear_point_issues,
    async_raise_issue,
)
from .services import async_setup_services

PLATFORMS = [
    Platform.BINARY_SENSOR,
    Platform.DATETIME,
    Platform.NUMBER,
    Platform.SENSOR,
    Platform.SWITCH,
    Platform.TEXT,
]
CONFIG_SCHEMA = cv.config_entry_only_config_schema(DOMAIN)


async def async_setup(hass: HomeAssistant, config: ConfigType) -> bool:
    """Register the actions, once for every PLC."""
    async_setup_services(hass)
    return True


async def async_setup_entry(hass: HomeAssistant, entry: PlcBridgeConfigEntry) -> bool:
    """Connect to the PLC, poll it once, then add its entities."""
    if entry.data.get(CONF_TLS) == TlsMode.OFF:
        async_raise_issue(hass, entry, TLS_OFF)
    else:
        async_clear_issue(hass, entry, TLS_OFF)
    client = create_client(hass, entry.data, entry.options)
    entry.async_on_unload(client.close)  # also when the setup below fails
    try:
        device = await client.connect()
    except PlcError as err:
        raise link_error(hass, entry, err, setup=True) from err
    async_clear_issue(hass, entry, CERTIFICATE_CHANGED)
    coordinator = PlcCoordinator(hass, entry, client)
    await coordinator.async_config_entry_first_refresh()
    entry.runtime_data = PlcRuntimeData(client=client, coordinator=coordinator, device=device)
    await hass.config_entries.async_forward_entry_setups(entry, PLATFORMS)
    entry.async_on_unload(entry.add_update_listener(async_reload_entry))
    return True


async def async_reload_entry(hass: HomeAssistant, entry: PlcBridgeConfigEntry) -> None:
    """Apply changed options, connection or points (subentries) by setting the PLC up again."""
    await hass.config_entries.async_reload(entry.entry_id)


async def async_unload_entry(hass: HomeAssistant, entry: PlcBridgeConfigEntry) -> bool:
    """Remove the entities; the client logs out and closes as the entry unloads."""
    return await hass.config_entries.async_unload_platforms(entry, PLATFORMS)


async def async_remove_entry(hass: HomeAssistant, entry: ConfigEntry) -> None:
    """Delete the issues of a removed PLC."""
    for key in ISSUES:
        async_clear_issue(hass, entry, key)
    async_clear_point_issues(hass, entry)
