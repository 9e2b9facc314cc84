"""PLCnext values: the IEC types the REST interface carries, checks before a write, decoders.

The sources show values as JSON numbers, booleans and strings, and as strings of digits
(`"799244562"` for a DINT in the Groups page's example; pyPLCn writes `"500"`, `"true"`): every
decoder takes both forms. They say nothing of how dates and times travel; where they are
silent this module follows IEC 61131-3 and ISO 8601 (see `decode`), and says so.
"""

from __future__ import annotations

from datetime import UTC, date, datetime, timedelta, tzinfo
import math
import re
from typing import Any

from ...codec import (
    CHECKED,
    INTEGER_RANGES,
    check_iec,
    check_text,
    decode_error,
    iec_kinds,
    local_time,
    shortest_real,
    type_name,
)
from ...durations import DurationType, count_of, from_count
from ...errors import PlcValueError
from ...types import Value, ValueKind

INTEGERS = tuple(INTEGER_RANGES)
TYPES = ("BOOL", *INTEGERS, "REAL", "LREAL", "STRING", "WSTRING", "TIME", "LTIME", "DATE", "DT")
"""The elementary types a point may have, also the point form's data types."""
ALIASES = {"DATE_AND_TIME": "DT", "LDT": "DT", "LDATE": "DATE"}
KINDS = iec_kinds(TYPES, TIME=ValueKind.DURATION, LTIME=ValueKind.DURATION)
TIME_UNITS = {"TIME": 1_000_000, "LTIME": 1}
"""Nanoseconds a count of TIME (IEC: signed 32-bit ms) and LTIME (signed 64-bit ns) stands for."""
TIME_RANGES = {"TIME": INTEGER_RANGES["DINT"], "LTIME": INTEGER_RANGES["LINT"]}
DURATIONS = {
    kind: DurationType.of_count(kind, *TIME_RANGES[kind], TIME_UNITS[kind]) for kind in TIME_UNITS
}
"""LTIME is kept to the microsecond (a timedelta's): nanoseconds read are rounded to them."""
_LIMITS = {**INTEGER_RANGES, **TIME_RANGES}
MAX_STRING = 255  # no source gives PLCnext's STRING limit; the PLC refuses a longer one itself
_WHOLE = re.compile(r"\s*[+-]?\d{1,20}\s*", re.ASCII)
_TRUE, _FALSE = ("true", "1"), ("false", "0")


def data_type(text: str) -> str:
    """Return the canonical type name; raise PlcAddressError for a type the client lacks."""
    return type_name(text, TYPES, ALIASES)


def check_value(kind: str, value: Value, what: str) -> Value:
    """Return a value coerced for an IEC type; raise PlcValueError before anything is sent.

    A STRING holds one byte a character (IEC), a WSTRING UTF-16; TIME and LTIME are durations.
    """
    if kind in CHECKED:
        return check_iec(kind, value, what)
    if kind in DURATIONS:
        return DURATIONS[kind].check(value, what)
    if kind == "STRING":
        return check_text(value, MAX_STRING, what, encoding="latin-1", hint="; use a WSTRING")
    return check_text(value, MAX_STRING, what, kind=kind, encoding="utf-16")


def encode(kind: str, value: Value, zone: tzinfo) -> Any:
    """Return the JSON value of a checked value: numbers and booleans as JSON, dates as ISO text.

    A DT goes as ISO 8601 in UTC with its `Z` (the sources show no date; an aware ISO time is
    the one form no reader can take for another zone); a naive one is the PLC's local time.
    TIME and LTIME go as their counts (ms, ns), as they read.
    """
    if isinstance(value, timedelta):
        return count_of(value, TIME_UNITS[kind])
    if isinstance(value, datetime):
        if kind == "DATE":
            return f"{local_time(value, zone):%Y-%m-%d}"
        moment = value.replace(tzinfo=zone) if value.tzinfo is None else value
        try:
            moment = moment.astimezone(UTC)
        except OverflowError as err:
            raise PlcValueError(f"{value.isoformat()} has no time in UTC") from err
        return f"{moment:%Y-%m-%dT%H:%M:%S}.{moment.microsecond // 1000:03d}Z"
    return value


def decode(kind: str, raw: Any, zone: tzinfo, what: str) -> Value:
    """Return a point's value from its JSON; raise PlcProtocolError when it does not fit."""
    limits = _LIMITS.get(kind)
    if type(raw) is int and limits is not None and limits[0] <= raw <= limits[1]:
        return raw if kind not in TIME_UNITS else from_count(raw, TIME_UNITS[kind])
    if kind == "BOOL":
        return _bool(raw, what)
    if limits is not None:
        low, high = limits
        number = _whole(raw)
        if number is not None and low <= number <= high:
            return number if kind not in TIME_UNITS else from_count(number, TIME_UNITS[kind])
    elif kind in ("REAL", "LREAL"):
        real = _real(raw)
        if real is not None:
            return shortest_real(real) if kind == "REAL" else real
    elif kind in ("STRING", "WSTRING"):
        if isinstance(raw, str):
            return raw
    elif isinstance(raw, str) and (moment := parse_moment(kind, raw, zone)) is not None:
        return moment
    raise decode_error(kind, raw, what)


def _bool(raw: Any, what: str) -> bool:
    """Return a BOOL sent as true/false, 0/1 or their text."""
    if isinstance(raw, bool):
        return raw
    if isinstance(raw, int) and raw in (0, 1):
        return bool(raw)
    if isinstance(raw, str) and raw.strip().lower() in _TRUE + _FALSE:
        return raw.strip().lower() in _TRUE
    raise decode_error("BOOL", raw, what)


def _whole(raw: Any) -> int | None:
    """Return a whole number sent as a JSON number or as text; None for anything else."""
    if isinstance(raw, bool):
        return None
    if isinstance(raw, int):
        return raw
    if isinstance(raw, float) and math.isfinite(raw) and raw.is_integer():
        return int(raw)
    if isinstance(raw, str) and _WHOLE.fullmatch(raw):
        return int(raw)
    return None


def _real(raw: Any) -> float | None:
    """Return a finite number sent as a JSON number or as text; None for anything else."""
    if isinstance(raw, bool) or not isinstance(raw, int | float | str):
        return None
    try:
        number = float(raw)
    except (ValueError, OverflowError):
        return None
    return number if math.isfinite(number) else None


def parse_moment(kind: str, text: str, zone: tzinfo) -> datetime | None:
    """Return an ISO 8601 DATE or DT as an aware datetime; naive text is the PLC's time."""
    try:
        if kind == "DATE":
            day = date.fromisoformat(text.strip()[:10])
            return datetime(day.year, day.month, day.day, tzinfo=zone)
        moment = datetime.fromisoformat(text.strip())
    except ValueError:
        return None
    try:
        return moment.replace(tzinfo=zone) if moment.tzinfo is None else moment.astimezone(zone)
    except OverflowError:
        return None
