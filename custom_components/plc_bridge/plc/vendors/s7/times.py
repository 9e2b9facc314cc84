"""S7 durations, dates and BCD counts: TIME, S5TIME, TIME_OF_DAY, DATE and COUNTER.

As STEP 7 and TIA Portal define them: TIME is a DINT of milliseconds, TIME_OF_DAY a UDINT of
milliseconds since midnight, DATE a UINT of days since 1990-01-01, S5TIME three BCD digits with
a time base in bits 12-13 (10 ms, 100 ms, 1 s, 10 s; bits 14-15 are not evaluated), and a
counter three BCD digits (0..999).
"""

from __future__ import annotations

from contextlib import suppress
from datetime import date, datetime, timedelta, tzinfo
from decimal import Decimal
import math

from ...codec import check_integer, local_time
from ...durations import clock_duration
from ...errors import PlcProtocolError, PlcValueError
from ...types import Value

TIMES = ("TIME", "S5TIME", "TIME_OF_DAY", "DATE", "COUNTER")
DAY_MS = 86_400_000
MS_RANGES = {
    "TIME": (-(2**31), 2**31 - 1),
    "TIME_OF_DAY": (0, DAY_MS - 1),
    "S5TIME": (0, 999 * 10_000),
}
S5_BASES = (10, 100, 1_000, 10_000)
"""Milliseconds of S5TIME's time bases 0..3."""
EPOCH = date(1990, 1, 1)
LAST_DATE = date(2168, 12, 31)  # a DATE's last day as STEP 7 defines it (D#2168-12-31)
BCD_MAX = 999


def decode_time(kind: str, data: bytes, zone: tzinfo, what: str) -> Value:
    """Return a duration, a date (midnight in the PLC's zone) or a count from its bytes."""
    size = 2 if kind in ("S5TIME", "DATE", "COUNTER") else 4
    if len(data) < size:
        raise IndexError(what)
    word = int.from_bytes(data[:size], "big", signed=kind == "TIME")
    if kind in ("TIME", "TIME_OF_DAY"):
        if kind == "TIME_OF_DAY" and word >= DAY_MS:
            raise PlcProtocolError(f"{what} holds {word} ms, past the end of a day")
        return timedelta(milliseconds=word)
    if kind == "DATE":
        day = EPOCH + timedelta(days=word)
        if day > LAST_DATE:
            raise PlcProtocolError(f"{what} holds day {word}, after {LAST_DATE} (no S7 DATE)")
        return datetime(day.year, day.month, day.day, tzinfo=zone)
    if kind == "COUNTER" and word > 0x0FFF:
        raise PlcProtocolError(f"{what} holds {word:#06x}, no BCD count (0..999): read it as WORD")
    count = _bcd(word & 0x0FFF, what, kind)
    if kind == "COUNTER":
        return count
    return timedelta(milliseconds=count * S5_BASES[word >> 12 & 3])


def _bcd(word: int, what: str, kind: str) -> int:
    """Return the number three BCD digits spell; raise PlcProtocolError for a digit above 9."""
    digits = [word >> 8 & 0xF, word >> 4 & 0xF, word & 0xF]
    if any(digit > 9 for digit in digits):
        raise PlcProtocolError(f"{what} holds {word:#05x}, no {kind} (BCD digits 0..9)")
    return digits[0] * 100 + digits[1] * 10 + digits[2]


def check_time(kind: str, value: Value, what: str) -> Value:
    """Return the value a TIME, S5TIME, TIME_OF_DAY, DATE or COUNTER takes; raise PlcValueError."""
    if kind == "COUNTER":
        return check_integer(value, 0, BCD_MAX, what=what)
    if kind == "DATE":
        moment = _moment(value, what)
        _check_day(moment.date(), what)  # its own day; encode_time checks the PLC's again
        return moment
    milliseconds = _milliseconds(value, what)
    low, high = MS_RANGES[kind]
    if not low <= milliseconds <= high:
        raise PlcValueError(
            f"{what}: a {kind} holds {_seconds(low)}..{_seconds(high)} s, "
            f"not {_seconds(milliseconds)} s"
        )
    if kind == "S5TIME":
        _s5_base(milliseconds, what)
    return timedelta(milliseconds=milliseconds)


def _seconds(milliseconds: int) -> str:
    """Return milliseconds as seconds in plain decimals (-2147483.648, 9990)."""
    if abs(milliseconds) > 10**15:
        return f"{milliseconds / 1000:g}"
    return f"{Decimal(milliseconds).scaleb(-3):f}".rstrip("0").rstrip(".") or "0"


def _milliseconds(value: Value, what: str) -> int:
    """Return a duration (timedelta, seconds as a number or text, hh:mm:ss.zzz) in whole ms.

    The clock text is what a duration on the text platform shows: it takes it back.
    """
    if isinstance(value, str) and (clock := clock_duration(value)) is not None:
        value = clock
    if isinstance(value, timedelta):
        return round(value / timedelta(milliseconds=1))
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) <= 10**12:
        return value * 1000
    seconds = math.nan
    if isinstance(value, float):
        seconds = value * 1000
    elif isinstance(value, str):
        with suppress(ValueError):
            seconds = float(value.strip()) * 1000
    if not math.isfinite(seconds):
        raise PlcValueError(f"{what} takes a duration in seconds or as hh:mm:ss.zzz, not {value!r}")
    return round(seconds)


def _s5_base(milliseconds: int, what: str) -> int:
    """Return the finest time base that holds the duration exactly in three digits."""
    for number, base in enumerate(S5_BASES):
        if milliseconds % base == 0 and milliseconds // base <= BCD_MAX:
            return number
    coarse = next(base for base in S5_BASES if milliseconds // base <= BCD_MAX)
    below = milliseconds // coarse * coarse
    raise PlcValueError(
        f"{what}: an S5TIME of {milliseconds / 1000:g} s runs in steps of {coarse / 1000:g} s; "
        f"write {below / 1000:g} s or {(below + coarse) / 1000:g} s"
    )


def _moment(value: Value, what: str) -> datetime:
    """Return a date and time (or an ISO 8601 text) as a datetime."""
    if isinstance(value, datetime):
        return value
    if isinstance(value, str):
        try:
            return datetime.fromisoformat(value.strip())
        except ValueError:
            pass
    raise PlcValueError(f"{what} takes a date, not {value!r}")


def _check_day(day: date, what: str) -> date:
    """Return a day a DATE holds; raise PlcValueError for one outside 1990-01-01..2168-12-31."""
    if not EPOCH <= day <= LAST_DATE:
        raise PlcValueError(f"{what}: a DATE runs from {EPOCH} to {LAST_DATE}, not {day}")
    return day


def encode_time(kind: str, value: Value, zone: tzinfo, what: str) -> bytes:
    """Return the bytes of a checked TIME, S5TIME, TIME_OF_DAY, DATE or COUNTER."""
    if kind == "COUNTER":
        assert isinstance(value, int)
        return _to_bcd(value).to_bytes(2, "big")
    if kind == "DATE":
        assert isinstance(value, datetime)
        day = _check_day(local_time(value, zone).date(), what)
        return (day - EPOCH).days.to_bytes(2, "big")
    assert isinstance(value, timedelta)
    milliseconds = round(value / timedelta(milliseconds=1))
    if kind == "S5TIME":
        base = _s5_base(milliseconds, what)
        return (base << 12 | _to_bcd(milliseconds // S5_BASES[base])).to_bytes(2, "big")
    return milliseconds.to_bytes(4, "big", signed=kind == "TIME")


def _to_bcd(number: int) -> int:
    """Return three BCD digits of a number 0..999."""
    return number // 100 << 8 | number // 10 % 10 << 4 | number % 10
