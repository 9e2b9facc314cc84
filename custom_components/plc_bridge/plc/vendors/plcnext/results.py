"""PLCnext poll results: the points of a poll parsed once, and results kept while values repeat.

A poll of 10,000 points must not run Python code per point where nothing changed: the answer's
values are compared with the last poll's a list at a time, and only the changed ones decoded.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from datetime import tzinfo
from itertools import repeat
from typing import Any

from ...errors import PlcProtocolError
from ...types import Point, PointResult
from ...unchanged import LastResults
from .codec import decode
from .paths import VariablePath
from .placing import Reading

_ABSENT = object()  # a path with no value in the reading


@dataclass(slots=True)
class Plan:
    """Points parsed for a read: each path and type, the paths to ask, the points refused.

    A poll's plan also keeps its last results, reused where the PLC sends the same values.
    """

    points: tuple[Point, ...]
    wanted: list[tuple[Point, VariablePath, str]] = field(default_factory=list)
    paths: dict[str, VariablePath] = field(default_factory=dict)
    errors: dict[Point, PointResult] = field(default_factory=dict)
    clock: VariablePath | None = None  # a poll's: read in its group, at no request
    points_wanted: list[Point] = field(default_factory=list)  # by position in `wanted`
    keys: list[str] = field(default_factory=list)  # each wanted point's path key
    positions: dict[str, list[int]] = field(default_factory=dict)  # in `wanted`, by path key
    last: LastResults = field(default_factory=LastResults)

    def want(self, point: Point, path: VariablePath, kind: str) -> None:
        """Add a point whose path and type parsed."""
        self.positions.setdefault(path.key, []).append(len(self.wanted))
        self.wanted.append((point, path, kind))
        self.points_wanted.append(point)
        self.keys.append(path.key)
        self.paths.setdefault(path.key, path)


def results(reading: Reading, plan: Plan, zone: tzinfo) -> dict[Point, PointResult]:
    """Return the results of the plan's points from a reading, with those failed before.

    A value the PLC sent exactly as at the last poll keeps its last result: only the others
    are decoded (see `LastResults`).
    """
    found, failed, wanted = reading.found, reading.failed, plan.wanted

    def result_of(index: int, raw: Any) -> PointResult:
        """Decode one point's value, or give its error."""
        _point, path, kind = wanted[index]
        if raw is _ABSENT or path.key in failed:
            return outcome(reading, path, kind, zone)
        try:
            return PointResult(value=decode(kind, raw, zone, path.text))
        except PlcProtocolError as err:
            return PointResult(error=err)

    raws = list(map(found.get, plan.keys, repeat(_ABSENT)))
    also = (index for key in failed for index in plan.positions.get(key, ()))
    return plan.last.update(plan.points_wanted, raws, plan.errors, result_of, also)


def outcome(reading: Reading, path: VariablePath, kind: str, zone: tzinfo) -> PointResult:
    """Return one point's result from a reading."""
    if path.key in reading.failed:
        return PointResult(error=reading.failed[path.key])
    if path.key not in reading.found:
        return PointResult(error=PlcProtocolError(f"{path.text} is missing from the answer"))
    try:
        return PointResult(value=decode(kind, reading.found[path.key], zone, path.text))
    except PlcProtocolError as err:
        return PointResult(error=err)
