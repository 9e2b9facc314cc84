"""Config entry migrations: version 1 kept one point per subentry, version 2 devices of points.

Version 2.2: TecoApi TIME/TOD and PLCnext TIME/LTIME became durations; points made before keep
showing what they showed (see `kept_duration`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
import math
from types import MappingProxyType
from typing import Any

from homeassistant.components.sensor import CONF_STATE_CLASS
from homeassistant.config_entries import ConfigEntry, ConfigSubentry
from homeassistant.const import (
    CONF_DEVICE_CLASS,
    CONF_HOST,
    CONF_NAME,
    CONF_PORT,
    CONF_UNIT_OF_MEASUREMENT,
)
from homeassistant.core import HomeAssistant, callback
from homeassistant.helpers import device_registry as dr, entity_registry as er

from ..const import (
    CONF_AS_TEXT,
    CONF_BITS,
    CONF_DATA_TYPE,
    CONF_OFFSET,
    CONF_PLATFORM,
    CONF_POINTS,
    CONF_ROLE,
    CONF_SCALE,
    CONF_VALUE_MAP,
    CONF_VENDOR,
    DOMAIN,
    LOGGER,
    SUBENTRY_DEVICE,
    SUBENTRY_POINT,
)
from .conversion import LINEAR_KEYS
from .duration_units import UNITS

TECOMAT_TIMES = ("TIME", "TOD", "TIME_OF_DAY")
PLCNEXT_COUNTS = {"TIME": ("DINT", 1e-3), "LTIME": ("LINT", 1e-9)}
"""PLCnext times as version 2.1 showed them: the integer type alike, and seconds a count."""
NOT_A_DURATION = (CONF_ROLE, CONF_VALUE_MAP, CONF_BITS, *LINEAR_KEYS)
"""What only an integer point has: a part of an entity of several points, labels, bits, ranges."""


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


@callback
def async_migrate_address_keys(hass: HomeAssistant, entry: ConfigEntry[Any]) -> None:
    """Key a version 1 PLC's device and entities by its entry where the first builds used host:port.

    The first 0.1.0 builds keyed a PLC without serial or MAC (its unique id is then host:port)
    by that unique id; later ones by the entry id, which a move with Reconfigure leaves alone.
    Left as they were, such entities would be registered anew beside the old ones: new entity
    ids, history lost. Re-keyed, each keeps its registry entry and entity id.
    """
    address = f"{entry.data.get(CONF_HOST)}:{entry.data.get(CONF_PORT)}"
    if entry.unique_id != address:
        return
    entities = er.async_get(hass)
    for entity in er.async_entries_for_config_entry(entities, entry.entry_id):
        key = entity.unique_id.removeprefix(f"{address}_")
        if key != entity.unique_id:
            entities.async_update_entity(entity.entity_id, new_unique_id=f"{entry.entry_id}_{key}")
    devices = dr.async_get(hass)
    for device in dr.async_entries_for_config_entry(devices, entry.entry_id):
        if (DOMAIN, address) in device.identifiers:
            devices.async_update_device(device.id, new_identifiers={(DOMAIN, entry.entry_id)})


@callback
def async_migrate_durations(
    hass: HomeAssistant, entry: ConfigEntry[Any], times_in_seconds: Callable[[], None]
) -> None:
    """Version 2.2: rewrite the TecoApi and PLCnext time points so each shows what it showed.

    `times_in_seconds` raises the repair issue that says what the migration cannot reach.
    """
    vendor = str(entry.data.get(CONF_VENDOR))
    for subentry in list(entry.subentries.values()):
        points = subentry.data.get(CONF_POINTS, {})
        kept = {point_id: kept_duration(vendor, data) for point_id, data in points.items()}
        if subentry.subentry_type == SUBENTRY_DEVICE and kept != points:
            data = {**subentry.data, CONF_POINTS: kept}
            hass.config_entries.async_update_subentry(entry, subentry, data=data)
    if vendor in ("tecomat", "plcnext"):
        # The read and write actions now take and give seconds where they took milliseconds
        # (PLCnext) or text (TecoApi): automations are out of the migration's reach, so say so.
        times_in_seconds()
    hass.config_entries.async_update_entry(entry, minor_version=2)


def kept_duration(vendor: str, data: Mapping[str, Any]) -> dict[str, Any]:
    """Return a point's data that shows, as a duration, what version 2.1 showed of it.

    A TecoApi TIME or TOD showed text: it keeps showing it (`as_text`). A PLCnext TIME or LTIME
    showed a count: as a sensor or number of a time unit the count and scale make (1 ms, or
    1 µs for an LTIME scaled by 0.001) with no other unit given, it becomes a duration in that
    unit (Home Assistant converts durations); otherwise it is read as the integer it showed.
    """
    kind = str(data.get(CONF_DATA_TYPE, "")).strip().upper()
    if vendor == "tecomat" and kind in TECOMAT_TIMES:
        return {**data, CONF_AS_TEXT: True}
    if vendor != "plcnext" or kind not in PLCNEXT_COUNTS:
        return dict(data)
    integer, seconds = PLCNEXT_COUNTS[kind]
    unit = count_unit(data, seconds)
    if unit is None:
        return {**data, CONF_DATA_TYPE: integer}
    kept = {key: value for key, value in data.items() if key != CONF_DEVICE_CLASS}
    return kept | {CONF_UNIT_OF_MEASUREMENT: unit, CONF_SCALE: 1.0, CONF_OFFSET: 0.0}


def count_unit(data: Mapping[str, Any], seconds: float) -> str | None:
    """Return the time unit a PLCnext count of `seconds` showed in, None when it showed no unit.

    A point with no unit but a state class keeps its count: statistics would see a unit appear.
    """
    if data.get(CONF_PLATFORM) not in ("sensor", "number") or any(
        key in data for key in NOT_A_DURATION
    ):
        return None
    if float(data.get(CONF_OFFSET, 0.0)) or data.get(CONF_DEVICE_CLASS) not in (None, "duration"):
        return None
    shown = seconds / float(data.get(CONF_SCALE, 1.0))  # the seconds one shown unit stands for
    unit = next(
        (name for name, size in UNITS.items() if math.isclose(size.total_seconds(), shown)), None
    )
    given = data.get(CONF_UNIT_OF_MEASUREMENT) or None
    if unit is None or given not in (None, unit) or (given is None and data.get(CONF_STATE_CLASS)):
        return None
    return unit


async def async_migrate_entry(
    hass: HomeAssistant, entry: ConfigEntry[Any], times_in_seconds: Callable[[], None]
) -> bool:
    """Migrate an entry of an older version; refuse one from a newer release."""
    if entry.version > 2:
        return False
    if entry.version == 1:
        async_migrate_address_keys(hass, entry)
        async_migrate_points(hass, entry)
    if entry.minor_version < 2:
        async_migrate_durations(hass, entry, times_in_seconds)
    return True
