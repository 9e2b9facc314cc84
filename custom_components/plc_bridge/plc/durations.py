"""Durations shared by vendors: checks before a write, counts in a PLC's unit, clock text.

A duration is a `timedelta` in both layers. A written one comes as a timedelta, a number of
seconds, or text: seconds, or a clock `hh:mm:ss.zzz` (hours past 24 allowed, as TecoApi writes
TIME). A timedelta holds microseconds: a count in nanoseconds (LTIME) is rounded to them.
"""

from __future__ import annotations

from contextlib import suppress
from dataclasses import dataclass
from datetime import timedelta
from decimal import Decimal
import math
import re

from .errors import PlcValueError
from .types import Value

MILLISECOND = timedelta(milliseconds=1)
MICROSECOND = timedelta(microseconds=1)
_CLOCK = re.compile(r"([+-]?)(\d+):([0-5]\d):([0-5]\d)(?:\.(\d{1,6}))?", re.ASCII)


@dataclass(frozen=True, slots=True)
class DurationType:
    """A PLC duration type: its range and the step (the unit) it counts in."""

    name: str
    low: timedelta
    high: timedelta
    step: timedelta = MILLISECOND

    @classmethod
    def of_count(cls, name: str, low: int, high: int, nanoseconds: int) -> DurationType:
        """Return a type held as a count of `nanoseconds` (1_000_000: ms) within [low, high]."""
        if nanoseconds >= 1000:
            step = timedelta(microseconds=nanoseconds // 1000)
            return cls(name, low * step, high * step, step)
        per = 1000 // nanoseconds  # counts a microsecond: only whole ones inside the range
        return cls(
            name,
            timedelta(microseconds=-(-low // per)),
            timedelta(microseconds=high // per),
            MICROSECOND,
        )

    def check(self, value: Value, what: str) -> timedelta:
        """Return a written value as a duration of this type; raise PlcValueError if it is none."""
        duration = _duration(value, self.name, what)
        steps, rest = divmod(duration, self.step)
        steps += rest * 2 >= self.step
        if not self.low // self.step <= steps <= self.high // self.step:
            raise PlcValueError(
                f"{what}: a {self.name} holds {seconds_text(self.low)}..{seconds_text(self.high)}"
                f" s, not {seconds_text(duration)} s"
            )
        return steps * self.step


def from_count(count: int, nanoseconds: int) -> timedelta:
    """Return a count of `nanoseconds` read from a PLC as a duration, to the microsecond."""
    return timedelta(microseconds=round(Decimal(count) * nanoseconds / 1000))


def count_of(duration: timedelta, nanoseconds: int) -> int:
    """Return a checked duration as a whole count of `nanoseconds` (exact: it is on its step)."""
    return duration // MICROSECOND * 1000 // nanoseconds


def _duration(value: Value, kind: str, what: str) -> timedelta:
    """Return a timedelta, a number of seconds or a duration text as a timedelta."""
    if isinstance(value, timedelta):
        return value
    seconds: float | int | None = None
    if isinstance(value, int | float) and not isinstance(value, bool):
        seconds = value
    elif isinstance(value, str):
        if (clock := clock_duration(value)) is not None:
            return clock
        with suppress(ValueError):
            seconds = float(value.strip())
    if seconds is not None and (isinstance(seconds, int) or math.isfinite(seconds)):
        with suppress(OverflowError):
            return timedelta(seconds=seconds)
        raise PlcValueError(f"{what}: the number is outside the range of a {kind}")
    raise PlcValueError(f"{what} takes a {kind} in seconds or as hh:mm:ss.zzz, not {value!r}")


def clock_duration(text: str) -> timedelta | None:
    """Return a duration written as [-]hh:mm:ss[.zzz] (any number of hours), else None."""
    match = _CLOCK.fullmatch(text.strip())
    if match is None:
        return None
    sign, hours, minutes, seconds, fraction = match.groups()
    try:
        duration = timedelta(
            hours=int(hours),
            minutes=int(minutes),
            seconds=int(seconds),
            microseconds=int((fraction or "0").ljust(6, "0")),
        )
    except OverflowError:
        return None
    return -duration if sign == "-" else duration


def clock_text(duration: timedelta) -> str:
    """Return a duration as hh:mm:ss.zzz (hours past 24 kept; microseconds when it has them)."""
    micros = abs(duration) // MICROSECOND
    seconds, micros = divmod(micros, 1_000_000)
    minutes, seconds = divmod(seconds, 60)
    hours, minutes = divmod(minutes, 60)
    fraction = f"{micros:06d}" if micros % 1000 else f"{micros // 1000:03d}"
    sign = "-" if duration < timedelta(0) else ""
    return f"{sign}{hours:02d}:{minutes:02d}:{seconds:02d}.{fraction}"


def seconds_text(duration: timedelta) -> str:
    """Return a duration as seconds in plain decimals (-2147483.648, 90)."""
    text = f"{Decimal(duration // MICROSECOND).scaleb(-6):f}"
    return text.rstrip("0").rstrip(".") if "." in text else text
