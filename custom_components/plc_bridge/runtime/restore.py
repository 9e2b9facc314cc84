"""Restored values: an entity's raw point values as Home Assistant stores them across restarts.

An entity stores the raw value of each of its points (by role) with its state; at the next
start it shows them, marked restored, until a poll reads its points. They are only ever shown:
nothing decides a write from them (entity.py).
"""

from __future__ import annotations

from collections.abc import Mapping
from datetime import datetime, timedelta
from typing import Any, Final

from homeassistant.helpers.restore_state import ExtraStoredData, RestoredExtraData

from ..plc import PointResult, Value

VALUES: Final = "values"
"""The key of the raw values, by role, in an entity's stored extra data."""
DATETIME: Final = "datetime"
SECONDS: Final = "seconds"


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


def stored_values(extra: ExtraStoredData | None) -> Mapping[str, Any] | None:
    """Return the raw values an entity stored (Home Assistant's own dict, not a copy), if any."""
    values = extra.as_dict().get(VALUES) if extra is not None else None
    return values if isinstance(values, Mapping) and values else None


def restored_result(values: Mapping[str, Any] | None, role: str) -> PointResult | None:
    """Return a role's restored value as a result, None where none was stored."""
    if values is None or (value := decoded(values.get(role))) is None:
        return None
    return PointResult(value=value)


def extra_data(
    results: Mapping[str, PointResult | None], restored: Mapping[str, Any] | None
) -> ExtraStoredData | None:
    """Return what an entity stores: each role's last value read, else the one it restored."""
    values: dict[str, Any] = {}
    for role, result in results.items():
        if result is not None and result.ok and result.value is not None:
            values[role] = encoded(result.value)
        elif result is None and restored is not None and role in restored:
            values[role] = restored[role]
    return RestoredExtraData({VALUES: values}) if values else None
