"""Poll classes: a point is read fast, normal (the PLC's poll interval) or slow.

The coordinator polls at the fastest interval a class with points needs (its tick); each poll
reads, in one planned read, the points of the classes due then, the points never read yet and
those a write asks back. A class is due at the tick nearest its interval since it was last
read. Points without a class (a machine's availability point) are read at every poll. Where
every point has one class, every poll reads every point: a PLC without fast or slow points is
polled as before poll classes existed. The first poll after a failed one reads every point.
"""

from __future__ import annotations

from collections.abc import Collection, Container, Iterable, Mapping, Sequence
import math
from typing import Any, Final

from homeassistant.const import CONF_SCAN_INTERVAL
from homeassistant.helpers.selector import SelectSelector, SelectSelectorConfig
import voluptuous as vol

from .plc import PlcClient, Point

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


UNPOLLED: Final = frozenset({"button"})
"""Platforms whose points are only written (a button, pulsed or not): they have no class."""


def has_poll_class(platform: str) -> bool:
    """True for a platform whose point shows a value, so has a poll class (not a button)."""
    return platform not in UNPOLLED


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


class PollSchedule:
    """Which points each poll reads: every class at its own interval, on the fastest's ticks."""

    def __init__(self) -> None:
        """Start with every point normal."""
        self.classes: dict[Point, str] = {}
        self.intervals: dict[str, float] = {}  # of the classes that have points
        self._normal = 0.0
        self._read: dict[str, float] = {}  # when each class was last read (a poll's time)

    def configure(self, classes: Mapping[Point, str], intervals: Mapping[str, float]) -> None:
        """Take each point's class (points left out: read at every poll) and the intervals."""
        self.classes = dict(classes)
        used = set(self.classes.values())
        self.intervals = {name: intervals[name] for name in POLL_CLASSES if name in used}
        self._normal = intervals[NORMAL]
        self._read = {name: at for name, at in self._read.items() if name in self.intervals}

    @property
    def tick(self) -> float:
        """Seconds between polls: the interval of the fastest class with points."""
        return min(self.intervals.values(), default=self._normal)

    def due(
        self, points: list[Point], at: float, read: Container[Point], wanted: Collection[Point]
    ) -> tuple[list[Point], set[str]]:
        """Return the points a poll at `at` reads, and the classes it reads.

        `read`: the points read before (others are read at once); `wanted`: points a write
        asks back. Where every class is due, or there is only one, `points` itself is returned.
        """
        if len(self.intervals) <= 1:
            return points, set(self.intervals)
        half = self.tick / 2
        due = {
            name
            for name, interval in self.intervals.items()
            if at - self._read.get(name, -math.inf) >= interval - half
        }
        if len(due) == len(self.intervals):
            return points, due
        return [
            point
            for point in points
            if (name := self.classes.get(point)) is None
            or name in due
            or point not in read
            or point in wanted
        ], due

    def done(self, at: float, classes: Iterable[str]) -> None:
        """Note that a poll at `at` read these classes."""
        for name in classes:
            self._read[name] = at

    def counts(self) -> dict[str, int]:
        """Return how many points each class has."""
        counts = dict.fromkeys(self.intervals, 0)
        for name in self.classes.values():
            counts[name] += 1
        return counts
