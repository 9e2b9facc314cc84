"""Durations in Home Assistant: the time unit a duration point is shown and set in, or clock text.

A duration sensor or number shows its point in seconds unless the point names another time
unit (a PLCnext TIME that showed milliseconds keeps `ms`); Home Assistant converts from there.
A point with `as_text` (or on the text platform) shows hh:mm:ss.zzz instead.
"""

from __future__ import annotations

from datetime import timedelta

from homeassistant.const import UnitOfTime

UNITS: dict[str, timedelta] = {
    UnitOfTime.MICROSECONDS: timedelta(microseconds=1),
    UnitOfTime.MILLISECONDS: timedelta(milliseconds=1),
    UnitOfTime.SECONDS: timedelta(seconds=1),
    UnitOfTime.MINUTES: timedelta(minutes=1),
    UnitOfTime.HOURS: timedelta(hours=1),
    UnitOfTime.DAYS: timedelta(days=1),
}
"""The units a duration point can be shown in (those of Home Assistant's duration class)."""
COUNTED = (UnitOfTime.MICROSECONDS, UnitOfTime.MILLISECONDS)
"""Units below the second, whose whole counts show as integers (1500 ms, as a count did)."""


def duration_unit(unit: str | None) -> UnitOfTime:
    """Return the unit a duration point with this stored unit is shown in: it, else seconds."""
    return UnitOfTime(unit) if unit in UNITS else UnitOfTime.SECONDS


def in_unit(duration: timedelta, unit: str) -> int | float:
    """Return a duration as a number of `unit` (whole milliseconds as an integer)."""
    size = UNITS[unit]
    if unit in COUNTED and not duration % size:
        return duration // size
    return duration / size


def of_unit(value: float, unit: str) -> timedelta | float:
    """Return a number of `unit` as a duration (to the microsecond); seconds past timedelta's.

    The vendor's check refuses those seconds as outside its type, before anything is sent.
    """
    try:
        return UNITS[unit] * value
    except OverflowError:
        return value * UNITS[unit].total_seconds()
