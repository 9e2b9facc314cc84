"""Actions of PLC Bridge: write and read points by address, and set the PLC clock."""

from __future__ import annotations

from datetime import datetime, timedelta
from typing import Any

from homeassistant.config_entries import ConfigEntryState
from homeassistant.core import (
    HomeAssistant,
    ServiceCall,
    ServiceResponse,
    SupportsResponse,
    callback,
)
from homeassistant.exceptions import ServiceValidationError
from homeassistant.helpers import config_validation as cv
from homeassistant.helpers.service import async_register_admin_service
from homeassistant.util import dt as dt_util
import voluptuous as vol

from .const import (
    ATTR_CONFIG_ENTRY_ID,
    ATTR_POINTS,
    ATTR_VALUE,
    CONF_ADDRESS,
    CONF_DATA_TYPE,
    DOMAIN,
    SUBENTRY_DEVICE,
)
from .coordinator import PlcBridgeConfigEntry
from .model.config_file import dump_config
from .model.point_table import export_points
from .model.points import entry_points
from .plc import PlcClient, PlcError, Point, Value
from .runtime.errors import invalid, translated_errors

SERVICE_WRITE = "write"
SERVICE_READ = "read"
SERVICE_SYNC_CLOCK = "sync_clock"
SERVICE_EXPORT_POINTS = "export_points"
SERVICE_EXPORT_CONFIG = "export_config"

POINT = {vol.Required(CONF_ADDRESS): cv.string, vol.Required(CONF_DATA_TYPE): cv.string}
VALUE = vol.Any(bool, int, float, str, [vol.Coerce(int)])
ENTRY_SCHEMA = vol.Schema({vol.Required(ATTR_CONFIG_ENTRY_ID): cv.string})
MAX_READ = 100
"""Points one read action may name: at most a few requests, even at an S7-200 SMART's pace."""
ONE_POINT = {vol.Optional(CONF_ADDRESS): cv.string, vol.Optional(CONF_DATA_TYPE): cv.string}
"""One point in fields of its own, as the action's form offers it (the list is for scripts)."""
WRITE_SCHEMA = ENTRY_SCHEMA.extend(
    {
        **ONE_POINT,
        vol.Optional(ATTR_VALUE): VALUE,
        vol.Optional(ATTR_POINTS): vol.All(
            cv.ensure_list, [vol.Schema({**POINT, vol.Required(ATTR_VALUE): VALUE})], vol.Length(1)
        ),
    }
)
READ_SCHEMA = ENTRY_SCHEMA.extend(
    {
        **ONE_POINT,
        vol.Optional(ATTR_POINTS): vol.All(
            cv.ensure_list, [vol.Schema(POINT)], vol.Length(1, MAX_READ)
        ),
    }
)


def named_points(call: ServiceCall, *fields: str) -> list[dict[str, Any]]:
    """Return the points an action names: its list, or the one point of its own fields.

    Both, or neither, or a point lacking one of `fields`, is refused before anything is sent.
    """
    single = {key: call.data[key] for key in fields if key in call.data}
    listed: list[dict[str, Any]] | None = call.data.get(ATTR_POINTS)
    if bool(single) == bool(listed):
        raise ServiceValidationError(translation_domain=DOMAIN, translation_key="one_point_or_list")
    if listed:
        return listed
    if missing := [key for key in fields if key not in single]:
        raise ServiceValidationError(
            translation_domain=DOMAIN,
            translation_key="point_incomplete",
            translation_placeholders={"fields": ", ".join(missing)},
        )
    return [single]


def named_entry(call: ServiceCall) -> PlcBridgeConfigEntry:
    """Return the PLC the action names, set up or not."""
    entry_id: str = call.data[ATTR_CONFIG_ENTRY_ID]
    entry: PlcBridgeConfigEntry | None = call.hass.config_entries.async_get_entry(entry_id)
    if entry is None or entry.domain != DOMAIN:
        raise ServiceValidationError(
            translation_domain=DOMAIN,
            translation_key="entry_not_found",
            translation_placeholders={"entry_id": entry_id},
        )
    return entry


def loaded_entry(call: ServiceCall) -> PlcBridgeConfigEntry:
    """Return the PLC the action names; it must be set up."""
    entry = named_entry(call)
    if entry.state is not ConfigEntryState.LOADED:
        raise ServiceValidationError(
            translation_domain=DOMAIN,
            translation_key="entry_not_loaded",
            translation_placeholders={"title": entry.title},
        )
    return entry


def checked_point(client: PlcClient, item: dict[str, Any]) -> Point:
    """Return an action's point with its address normalized; refuse an invalid one."""
    try:
        return client.validate_point(Point(item[CONF_ADDRESS], item[CONF_DATA_TYPE]))
    except PlcError as err:
        raise invalid("invalid_address", err) from err


def checked_value(client: PlcClient, point: Point, value: Value) -> Value:
    """Return the value coerced for the point; refuse one that does not fit."""
    try:
        return client.validate_value(point, value)
    except PlcError as err:
        raise invalid("invalid_value", err) from err


async def async_write(call: ServiceCall) -> None:
    """Write every given point in one request, all checked before anything is sent."""
    entry = loaded_entry(call)
    client = entry.runtime_data.client
    coordinator = entry.runtime_data.coordinator
    values: dict[Point, Value] = {}
    for item in named_points(call, CONF_ADDRESS, CONF_DATA_TYPE, ATTR_VALUE):
        point = checked_point(client, item)
        coordinator.write_guard.check(point)
        values[point] = checked_value(client, point, item[ATTR_VALUE])
    await coordinator.async_write(values)


async def async_read(call: ServiceCall) -> ServiceResponse:
    """Read the given points in one poll; return each value, or its error."""
    entry = loaded_entry(call)
    client = entry.runtime_data.client
    points = [
        checked_point(client, item) for item in named_points(call, CONF_ADDRESS, CONF_DATA_TYPE)
    ]
    with translated_errors(call.hass, entry):
        result = await client.read(points, poll=False)
    values: dict[str, Any] = {}
    errors: dict[str, Any] = {}
    for point in points:
        outcome = result.values.get(point)
        values[point.address] = json_value(outcome.value) if outcome and outcome.ok else None
        if outcome is None or outcome.error is not None:
            errors[point.address] = str(outcome.error if outcome else "no answer for this point")
    return {"values": values, "errors": errors}


def json_value(value: Value | None) -> Any:
    """Return a point value as action responses carry it (ISO 8601 dates, durations in s)."""
    if isinstance(value, timedelta):
        return value.total_seconds()
    return value.isoformat() if isinstance(value, datetime) else value


async def async_export_points(call: ServiceCall) -> ServiceResponse:
    """Return the PLC's points as the table the device flow imports, and by device."""
    entry = loaded_entry(call)
    configs = entry_points(entry).values()
    devices: dict[str, Any] = {
        subentry.title: export_points(
            config.stored() for config in configs if config.subentry_id == subentry_id
        )
        for subentry_id, subentry in entry.subentries.items()
        if subentry.subentry_type == SUBENTRY_DEVICE  # not the exposes
    }
    return {"points": export_points(config.stored() for config in configs), "devices": devices}


async def async_export_config(call: ServiceCall) -> ServiceResponse:
    """Return the whole PLC as the file the config flow takes, secrets left out.

    Read from the stored entry: it works while the PLC cannot be reached, too.
    """
    return {"yaml": dump_config(named_entry(call))}


async def async_sync_clock(call: ServiceCall) -> None:
    """Set the PLC clock to Home Assistant's time."""
    await loaded_entry(call).runtime_data.coordinator.async_set_clock(dt_util.now())


@callback
def async_setup_services(hass: HomeAssistant) -> None:
    """Register the actions (once, for every PLC), all for administrators only.

    Reading by address reaches any memory of the PLC, not only the points shown to users, and
    holds the PLC's request lock; the exports list every address.
    """
    async_register_admin_service(hass, DOMAIN, SERVICE_WRITE, async_write, schema=WRITE_SCHEMA)
    async_register_admin_service(
        hass, DOMAIN, SERVICE_READ, async_read, READ_SCHEMA, SupportsResponse.ONLY
    )
    async_register_admin_service(
        hass, DOMAIN, SERVICE_SYNC_CLOCK, async_sync_clock, schema=ENTRY_SCHEMA
    )
    async_register_admin_service(
        hass,
        DOMAIN,
        SERVICE_EXPORT_POINTS,
        async_export_points,
        ENTRY_SCHEMA,
        SupportsResponse.ONLY,
    )
    async_register_admin_service(
        hass,
        DOMAIN,
        SERVICE_EXPORT_CONFIG,
        async_export_config,
        ENTRY_SCHEMA,
        SupportsResponse.ONLY,
    )
