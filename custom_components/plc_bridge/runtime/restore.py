"""Restored values: an entity's raw point values as Home Assistant stores them across restarts.

An entity stores the raw value of each of its points (by address and data type, so that a
value is never shown for another address after an edit) with its state; at the next start it
shows them, marked restored, until a poll reads its points. They are only ever shown: nothing
decides a write from them (entity.py).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from datetime import datetime, timedelta
from typing import Any, Final

from homeassistant.helpers.restore_state import ExtraStoredData, RestoredExtraData

from ..plc import Point, PointResult, Value

VALUES: Final = "values"
"""The key of the raw values, by point, in an entity's stored extra data."""
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


def stored_values(
    extra: ExtraStoredData | None, unread: Iterable[Point]
) -> Mapping[str, Any] | None:
    """Return the raw values an entity stored (HA's own dict) if one is of a point not read yet.

    Home Assistant keeps the dict for the whole run: the entity refers to it, copying nothing.
    """
    values = extra.as_dict().get(VALUES) if extra is not None else None
    if not isinstance(values, Mapping) or not any(point_key(p) in values for p in unread):
        return None
    return values


def restored_result(values: Mapping[str, Any] | None, point: Point) -> PointResult | None:
    """Return a point's restored value as a result, None where none was stored."""
    if values is None or (value := decoded(values.get(point_key(point)))) is None:
        return None
    return PointResult(value=value)


def extra_data(
    results: Mapping[Point, PointResult | None], restored: Mapping[str, Any] | None
) -> ExtraStoredData | None:
    """Return what an entity stores: each point's last value read, else the one it restored."""
    values: dict[str, Any] = {}
    for point, result in results.items():
        key = point_key(point)
        if result is not None and result.ok and result.value is not None:
            values[key] = encoded(result.value)
        elif result is None and restored is not None and key in restored:
            values[key] = restored[key]
    return RestoredExtraData({VALUES: values}) if values else None
