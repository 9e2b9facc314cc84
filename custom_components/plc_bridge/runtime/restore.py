"""Restored values: the raw values of one PLC's points, kept across restarts in a file of its own.

The coordinator keeps each point's raw value (by address and data type, so that a value is
never shown for another address after an edit) in one file per PLC: written when the entry
unloads, when Home Assistant stops, and a quarter of an hour after a poll (one write in each
quarter of an hour, as Home Assistant dumps its restored states, for a stop that writes
nothing). At the next start an entity shows its points' values, marked restored, until a poll
reads them; once every point has been read the values are dropped. They are only ever shown:
nothing decides a write from them (entity.py).

Version 0.10 stored the values with each entity's state in Home Assistant's restore data, which
keeps a copy of every entity's state for the whole run: the first start without the file takes
them from there (`async_get_stored_states`, public in every release the integration supports).
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Iterable, Mapping
from datetime import datetime, timedelta
from typing import Any, Final

from homeassistant.config_entries import ConfigEntry
from homeassistant.core import HomeAssistant, callback
from homeassistant.helpers import entity_registry as er
from homeassistant.helpers.restore_state import async_get as async_get_restore_data
from homeassistant.helpers.storage import Store

from ..const import DOMAIN
from ..plc import Point, PointResult, Value

VALUES: Final = "values"
"""The key of the raw values, by point, in the file (and in 0.10's extra data of an entity)."""
type Source = Callable[[], tuple[Mapping[Point, PointResult], Collection[Point]]]
"""What the values kept come from: the last poll's results, and the points kept."""
STORAGE_VERSION: Final = 1
SAVE_DELAY: Final = 900
"""Seconds from a poll to the file's write; polls meanwhile plan none (Home Assistant's own dump
interval of restored states)."""
DATETIME: Final = "datetime"
SECONDS: Final = "seconds"


def point_key(point: Point) -> str:
    """Return what names a point's value in the stored data: its address and data type."""
    return f"{point.address}|{point.data_type}"


def encoded(value: Value) -> Any:
    """Return a raw value as JSON (a date/time or a duration tagged with what it is)."""
    if isinstance(value, datetime):
        return {DATETIME: value.isoformat()}
    if isinstance(value, timedelta):
        return {SECONDS: value.total_seconds()}
    return value


def decoded(stored: Any) -> Value | None:
    """Return a stored raw value; None for anything the store cannot have made."""
    if isinstance(stored, Mapping):
        try:
            if DATETIME in stored:
                return datetime.fromisoformat(str(stored[DATETIME]))
            if SECONDS in stored:
                return timedelta(seconds=float(stored[SECONDS]))
        except (TypeError, ValueError):
            return None
        return None
    if isinstance(stored, list):
        return stored if all(isinstance(byte, int) for byte in stored) else None
    return stored if isinstance(stored, bool | int | float | str) else None


def restored_result(values: Mapping[str, Any] | None, point: Point) -> PointResult | None:
    """Return a point's restored value as a result, None where none was stored."""
    if values is None or (value := decoded(values.get(point_key(point)))) is None:
        return None
    return PointResult(value=value)


def storage_key(entry_id: str) -> str:
    """Return the name of a PLC's file of values."""
    return f"{DOMAIN}.values.{entry_id}"


async def async_remove_values(hass: HomeAssistant, entry_id: str) -> None:
    """Delete a removed PLC's file of values."""
    await Store[dict[str, Any]](hass, STORAGE_VERSION, storage_key(entry_id)).async_remove()


def _values_of_0_10(hass: HomeAssistant, entry: ConfigEntry[Any]) -> dict[str, Any]:
    """Return the raw values 0.10 stored with the entry's entities' states in Home Assistant."""
    registry = er.async_get(hass)
    ours = {item.entity_id for item in er.async_entries_for_config_entry(registry, entry.entry_id)}
    values: dict[str, Any] = {}
    for stored in async_get_restore_data(hass).async_get_stored_states():
        if stored.state.entity_id in ours and stored.extra_data is not None:
            found = stored.extra_data.as_dict().get(VALUES)
            if isinstance(found, Mapping):
                values.update(found)
    return values


class StoredValues:
    """One PLC's raw point values in its file: restored at the start, saved as they change."""

    def __init__(self, hass: HomeAssistant, entry: ConfigEntry[Any]) -> None:
        """Bind the file of the entry; nothing is read yet."""
        self._hass = hass
        self._entry = entry
        self._store = Store[dict[str, Any]](
            hass, STORAGE_VERSION, storage_key(entry.entry_id), atomic_writes=True
        )
        self.restored: Mapping[str, Any] | None = None
        """What the last stop left, until every point has been read once."""
        self._source: Source = lambda: ({}, ())
        self._pending = False

    async def async_load(self) -> None:
        """Read what the last stop left (at the first start after 0.10, from Home Assistant)."""
        stored = await self._store.async_load()
        if stored is None:
            values: Any = _values_of_0_10(self._hass, self._entry)
        else:
            values = stored.get(VALUES) if isinstance(stored, Mapping) else None
        self.restored = dict(values) if isinstance(values, Mapping) and values else None

    def follow(self, source: Source) -> None:
        """Keep the values of what `source` returns: the last results, the points kept."""
        self._source = source

    def restored_for(self, unread: Iterable[Point]) -> Mapping[str, Any] | None:
        """Return the restored values (one mapping for all) if one is of a point in `unread`."""
        values = self.restored
        if values is None or not any(point_key(point) in values for point in unread):
            return None
        return values

    @callback
    def polled(self, read: Collection[Point]) -> None:
        """After a poll: drop the restored values once every point is read; plan a save."""
        if self.restored is not None and all(point in read for point in self._source()[1]):
            self.restored = None
        if not self._pending:
            self._pending = True
            self._store.async_delay_save(self._data, SAVE_DELAY)

    async def async_save(self) -> None:
        """Write the values now (the entry unloads)."""
        await self._store.async_save(self._data())

    def _data(self) -> dict[str, Any]:
        """What the file holds: each point's last value read, else the one restored."""
        self._pending = False
        results, points = self._source()
        restored = self.restored or {}
        values: dict[str, Any] = {}
        for point in points:
            key = point_key(point)
            result = results.get(point)
            if result is not None and result.ok and result.value is not None:
                values[key] = encoded(result.value)
            elif result is None and key in restored:
                values[key] = restored[key]
        return {VALUES: values}
