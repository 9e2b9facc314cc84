"""Poll classes: a point is read fast, normal (the PLC's poll interval) or slow.

The coordinator polls at the fastest interval a class with points needs (its tick); each poll
reads, in one planned read, the points of the classes due then, the points never read yet and
those a write asks back. A class is due at the tick nearest its interval since it was last
read. Points without a class (a machine's availability point) are read at every poll. Where
every point has one class, every poll reads every point: a PLC without fast or slow points is
polled as before poll classes existed. The first poll after a failed one reads every point.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any, Final

from homeassistant.const import CONF_SCAN_INTERVAL
from homeassistant.helpers.selector import (
    SelectSelector,
    SelectSelectorConfig,
)
import voluptuous as vol

from ..plc import PlcClient, Point
from .kinds import KINDS

CONF_POLL: Final = "poll"
"""Point data: the point's poll class (absent: normal)."""
CONF_FAST_INTERVAL: Final = "fast_interval"
CONF_SLOW_INTERVAL: Final = "slow_interval"
FAST: Final = "fast"
NORMAL: Final = "normal"
SLOW: Final = "slow"
POLL_CLASSES: Final = (FAST, NORMAL, SLOW)
DEFAULT_FAST_INTERVAL: Final = 1.0
"""Seconds between reads of fast points, unless the vendor's pacing needs more."""
DEFAULT_SLOW_INTERVAL: Final = 60.0
"""Seconds between reads of slow points."""


def point_class(data: Mapping[str, Any]) -> str:
    """Return the poll class a point's data names (normal where it names none)."""
    value = data.get(CONF_POLL)
    return value if value in POLL_CLASSES else NORMAL


def poll_field() -> dict[vol.Marker, Any]:
    """Return a point form's poll class field (normal by default)."""
    return {
        vol.Required(CONF_POLL, default=NORMAL): SelectSelector(
            SelectSelectorConfig(options=list(POLL_CLASSES), translation_key=CONF_POLL)
        )
    }


def has_poll_class(platform: str) -> bool:
    """True for a platform whose point shows a value, so has a poll class (not a button)."""
    return platform not in KINDS or KINDS[platform].polled


def poll_data(
    values: Mapping[str, Any], *, polled: bool = True
) -> tuple[dict[str, Any], dict[str, str]]:
    """Return what a point stores of its poll class (nothing for normal), or the field's error.

    A point without a class (`polled` false: a button) stores none and takes only normal.
    """
    value = str(values.get(CONF_POLL) or NORMAL).strip().lower()
    if value not in POLL_CLASSES:
        return {}, {CONF_POLL: "poll_invalid"}
    if not polled and value != NORMAL:
        return {}, {CONF_POLL: "poll_not_for_button"}
    return ({CONF_POLL: value} if value != NORMAL else {}), {}


def class_minimums(
    client: type[PlcClient], classes: Mapping[Point, str], polled: Sequence[Point]
) -> dict[str, float]:
    """Return the shortest interval of each class the vendor's pacing allows.

    A fast poll reads the fast points and those read at every poll (`polled` without a
    class); a normal one every point, as the poll interval always did; a slow interval is
    never shorter than the normal one.
    """
    fast = [point for point in polled if classes.get(point, FAST) == FAST]
    normal = client.min_scan_interval(polled)
    return {FAST: client.min_scan_interval(fast), NORMAL: normal, SLOW: normal}


def class_intervals(
    client: type[PlcClient],
    options: Mapping[str, Any],
    classes: Mapping[Point, str],
    polled: Sequence[Point],
) -> dict[str, float]:
    """Return the interval of every class, as set in the options and the vendor allows.

    Kept in order (fast <= normal <= slow) for options stored before the slow and fast ones.
    """
    least = class_minimums(client, classes, polled)
    normal = max(
        float(options.get(CONF_SCAN_INTERVAL, client.default_scan_interval)), least[NORMAL]
    )
    fast = max(float(options.get(CONF_FAST_INTERVAL, DEFAULT_FAST_INTERVAL)), least[FAST])
    slow = float(options.get(CONF_SLOW_INTERVAL, DEFAULT_SLOW_INTERVAL))
    return {FAST: min(fast, normal), NORMAL: normal, SLOW: max(slow, normal)}


SECONDS_MIN = 0.1


SECONDS_MAX = 86400.0
"""The bounds of every poll interval, in seconds: the form's fields and the pasted file's."""


INTERVALS = (CONF_FAST_INTERVAL, CONF_SCAN_INTERVAL, CONF_SLOW_INTERVAL)


def interval_errors(intervals: dict[str, float], minimums: dict[str, float]) -> dict[str, str]:
    """Return the errors of the intervals by field: below the vendor's pace, or out of order."""
    fast, normal = intervals[CONF_FAST_INTERVAL], intervals[CONF_SCAN_INTERVAL]
    errors: dict[str, str] = {}
    if normal < minimums[NORMAL]:
        errors[CONF_SCAN_INTERVAL] = "scan_interval_too_short"
    if fast < minimums[FAST]:
        errors[CONF_FAST_INTERVAL] = "fast_interval_too_short"
    elif fast > normal:
        errors[CONF_FAST_INTERVAL] = "fast_above_normal"
    if intervals[CONF_SLOW_INTERVAL] < normal:
        errors[CONF_SLOW_INTERVAL] = "slow_below_normal"
    return errors


def unset(
    client: type[PlcClient], intervals: dict[str, float], minimums: dict[str, float]
) -> dict[str, float]:
    """Return the intervals with those not set yet filled in: defaults, kept in order."""
    normal = intervals.get(CONF_SCAN_INTERVAL, client.default_scan_interval)
    fast = min(max(DEFAULT_FAST_INTERVAL, minimums[FAST]), max(normal, minimums[FAST]))
    slow = max(DEFAULT_SLOW_INTERVAL, normal)
    defaults = {CONF_FAST_INTERVAL: fast, CONF_SCAN_INTERVAL: normal, CONF_SLOW_INTERVAL: slow}
    return defaults | intervals
