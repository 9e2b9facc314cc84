"""TecoApi values: the IEC types of chapter 4, their JSON forms, checks and a plain JSON writer."""

from __future__ import annotations

from datetime import datetime, timedelta, tzinfo
import json
import math
import re
from typing import Any

from ...codec import (
    CHECKED,
    INTEGER_RANGES,
    as_single,
    check_iec,
    check_text,
    decode_error,
    iec_kinds,
    local_time,
    plain_decimal,
    shortest_real,
    type_name,
)
from ...durations import MILLISECOND, DurationType, clock_duration, clock_text
from ...errors import PlcValueError
from ...types import Value, ValueKind

INTEGERS = ("BYTE", "WORD", "DWORD", "SINT", "INT", "DINT", "USINT", "UINT", "UDINT")
TYPES = ("BOOL", *INTEGERS, "REAL", "LREAL", "TIME", "TOD", "DATE", "DT", "STRING")
"""The elementary types of chapter 4, also the point form's data types."""
ALIASES = {"TIME_OF_DAY": "TOD", "DATE_AND_TIME": "DT"}
KINDS = iec_kinds(TYPES, TIME=ValueKind.DURATION, TOD=ValueKind.DURATION)  # sent "hh:mm:ss.zzz"
MAX_STRING = 255  # chapter 4: STRING holds at most 255 ASCII characters
MAX_VALUE = 255  # 3.6: an item's value is at most 255 characters in a PutObject body
MAX_TIME_MS = 2**31 - 1  # chapter 4: TIME runs from 0 to 24d 20:31:23.647
DAY_MS = 24 * 3600 * 1000
DURATIONS = {
    "TIME": DurationType.of_count("TIME", 0, MAX_TIME_MS, 1_000_000),
    "TOD": DurationType.of_count("TOD", 0, DAY_MS - 1, 1_000_000),  # since midnight
}

_DATE = re.compile(r"(\d{4})-(\d\d)-(\d\d)", re.ASCII)
_DT = re.compile(r"(\d{4})-(\d\d)-(\d\d)[T ](\d\d):(\d\d):(\d\d)(?:\.(\d{1,3}))?Z?", re.ASCII)


def data_type(text: str) -> str:
    """Return the canonical type name; raise PlcAddressError for a type TecoApi lacks."""
    return type_name(text, TYPES, ALIASES)


def check_value(kind: str, value: Value, what: str) -> Value:
    """Return a value coerced for an IEC type; raise PlcValueError before anything is sent."""
    if kind in CHECKED:
        checked = check_iec(kind, value, what)
        return _check_number(checked, what) if isinstance(checked, float) else checked
    if kind in DURATIONS:
        return DURATIONS[kind].check(value, what)
    return _check_text(value, what)


def _check_number(number: float, what: str) -> float:
    """Refuse a number whose digits, written without an exponent, pass the parser's limit."""
    length = len(plain_decimal(number))
    if length > MAX_VALUE:
        raise PlcValueError(
            f"{what}: {number!r} written without an exponent takes {length} characters; "
            f"the PLC reads numbers of at most {MAX_VALUE}"
        )
    return number


def _check_text(value: Value, what: str) -> str:
    """Return ASCII text the PutObject parser takes (3.6) that fits a STRING."""
    value = check_text(value, MAX_STRING, what)
    if len(json.dumps(value)) - 2 > MAX_VALUE:
        raise PlcValueError(f"{what}: with its escapes the text passes {MAX_VALUE} characters")
    return value


def encode(kind: str, value: Value, zone: tzinfo) -> Any:
    """Return the JSON value of a checked value; dates and times in the PLC's zone."""
    if isinstance(value, timedelta):
        return clock_text(value)  # chapter 4: TIME and TOD travel as "hh:mm:ss.zzz"
    if not isinstance(value, datetime):
        return value
    value = local_time(value, zone)
    if kind == "DATE":
        return f"{value:%Y-%m-%d}"
    # The spec's DT form ends in "Z", but the PLC prints its own clock digits (chapter 4
    # shows DT#...-11:22:33.456 as "...T11:22:33.456Z"): the digits are the PLC's local time.
    return f"{value:%Y-%m-%dT%H:%M:%S}.{value.microsecond // 1000:03d}Z"


def same_value(kind: str, held: Value, sent: Value, zone: tzinfo) -> bool:
    """True when a value read back is the one written, at the precision the PLC keeps and prints.

    Compared as sent (a DT keeps milliseconds, 4); a REAL as the 32-bit float it is stored in,
    and a REAL or LREAL also as printed with six decimals (chapter 4: "1000.000000"), so 1e-07
    reads back as 0.0 and 1234567.123456789 as 1234567.123457 (READINGS.md, "printed reals").
    """
    if (
        kind not in ("REAL", "LREAL")
        or not isinstance(held, int | float)
        or not isinstance(sent, int | float)
    ):
        return bool(encode(kind, held, zone) == encode(kind, sent, zone))
    stored, shown = float(sent), float(held)
    if kind == "REAL":
        stored, shown = _single(stored), _single(shown)
    if stored == shown:
        return True
    return abs(shown - stored) <= 5e-7 + 2 * math.ulp(max(abs(shown), abs(stored)))


def _single(value: float) -> float:
    """Return a float as the 32-bit float a REAL stores (unchanged when no REAL holds it)."""
    single = as_single(value)
    return value if single is None else single


def decode(kind: str, raw: Any, zone: tzinfo, what: str) -> Value:
    """Return the value of a point from its JSON; raise PlcProtocolError when it does not fit."""
    number = isinstance(raw, int | float) and not isinstance(raw, bool)
    if kind == "BOOL" and (isinstance(raw, bool) or raw in (0, 1)):
        return bool(raw)
    if kind in INTEGER_RANGES and number and float(raw).is_integer():
        low, high = INTEGER_RANGES[kind]
        if low <= raw <= high:
            return int(raw)
    if kind in ("REAL", "LREAL") and number:
        # The PLC prints a REAL with six decimals (4: "1000.000000"): 22.3 comes as 22.299999.
        return shortest_real(float(raw)) if kind == "REAL" else float(raw)
    if kind == "STRING" and isinstance(raw, str):
        return raw
    if isinstance(raw, str):
        text = raw.strip()
        if kind in DURATIONS and (duration := _clock(kind, text)) is not None:
            return duration
        if kind in ("DATE", "DT") and (moment := parse_datetime(kind, text, zone)):
            return moment
    raise decode_error(kind, raw, what)


def _clock(kind: str, text: str) -> timedelta | None:
    """Return a TIME or TOD the PLC sent as hh:mm:ss.zzz; None when it is none or off range."""
    duration = clock_duration(text)
    if duration is None or duration % MILLISECOND or not text[:1].isdigit():
        return None
    durations = DURATIONS[kind]
    return duration if durations.low <= duration <= durations.high else None


def parse_datetime(kind: str, text: str, zone: tzinfo) -> datetime | None:
    """Return a DATE ("YYYY-MM-DD") or DT ("YYYY-MM-DDThh:mm:ss.zzzZ") as an aware datetime."""
    match = (_DATE if kind == "DATE" else _DT).fullmatch(text.strip())
    if match is None:
        return None
    year, month, day, *clock = match.groups()
    hour, minute, second, fraction = clock or ("0", "0", "0", None)
    micro = int((fraction or "0").ljust(3, "0")) * 1000
    try:
        return datetime(
            int(year), int(month), int(day), int(hour), int(minute), int(second), micro, zone
        )
    except ValueError:
        return None


def _fits_real(value: float) -> bool:
    """True when a REAL could have printed this value (the PLC prints six decimals, 4).

    12345.678901 cannot come from a REAL (its nearest single is 12345.678711): an LREAL, then.
    A value a single holds exactly may still be an LREAL: the guess is marked as one.
    """
    if not math.isfinite(value):
        return True
    single = as_single(value)
    return single is not None and f"{single:.6f}" == f"{value:.6f}"


def guess_type(raw: Any) -> str | None:
    """Guess the IEC type of a value the PLC published (JSON does not say); None: not a leaf."""
    if isinstance(raw, bool):
        return "BOOL"
    if isinstance(raw, int):
        return "UDINT" if raw > INTEGER_RANGES["DINT"][1] else "DINT"
    if isinstance(raw, float):
        return "REAL" if _fits_real(raw) else "LREAL"
    if not isinstance(raw, str):
        return None
    text = raw.strip()
    if _DT.fullmatch(text) and "T" in text:
        return "DT"
    if _DATE.fullmatch(text):
        return "DATE"
    if clock_duration(text) is not None and text[:1].isdigit():
        return "TIME"
    return "STRING"


def dumps(value: Any) -> str:
    """Serialize JSON for the PutObject parser: compact, numbers never in exponent form (3.6)."""
    if isinstance(value, dict):
        members = (f"{json.dumps(key)}:{dumps(item)}" for key, item in value.items())
        return "{" + ",".join(members) + "}"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return plain_decimal(value)
    return json.dumps(value)
