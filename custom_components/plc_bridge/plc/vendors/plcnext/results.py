"""PLCnext poll results: the points of a poll parsed once, and results kept while values repeat.

A poll of 10,000 points must not run Python code per point where nothing changed: the answer's
values are compared with the last poll's a list at a time, and only the changed ones decoded.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from datetime import tzinfo
from itertools import compress, repeat
from operator import is_, is_not, ne
from typing import Any

from ...errors import PlcProtocolError
from ...types import Point, PointResult
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
    keys: list[str] = field(default_factory=list)  # each wanted point's path key
    positions: dict[str, list[int]] = field(default_factory=dict)  # in `wanted`, by path key
    raws: list[Any] | None = None  # the last poll's JSON values, by `wanted`
    results: dict[Point, PointResult] = field(default_factory=dict)  # the last poll's
    stale: set[int] = field(default_factory=set)  # positions with no result to reuse

    def want(self, point: Point, path: VariablePath, kind: str) -> None:
        """Add a point whose path and type parsed."""
        self.positions.setdefault(path.key, []).append(len(self.wanted))
        self.wanted.append((point, path, kind))
        self.keys.append(path.key)
        self.paths.setdefault(path.key, path)


def results(reading: Reading, plan: Plan, zone: tzinfo) -> dict[Point, PointResult]:
    """Return the results of the plan's points from a reading, with those failed before.

    A value the PLC sent exactly as at the last poll keeps its last result: decoding the same
    JSON value in the same zone gives the same value. Only the others are decoded, into a copy
    of the last results.
    """
    found, failed, wanted, stale = reading.found, reading.failed, plan.wanted, plan.stale
    raws = list(map(found.get, plan.keys, repeat(_ABSENT)))
    todo = changed(raws, plan.raws) | stale
    values = plan.results.copy() if plan.raws is not None else dict(plan.errors)
    for key in failed:
        todo.update(plan.positions.get(key, ()))
    for index in sorted(todo):
        point, path, kind = wanted[index]
        raw = raws[index]
        if raw is _ABSENT or path.key in failed:
            result = outcome(reading, path, kind, zone)
        else:
            try:
                result = PointResult(value=decode(kind, raw, zone, path.text))
            except PlcProtocolError as err:
                result = PointResult(error=err)
        values[point] = result
        if result.ok:
            stale.discard(index)
        else:
            stale.add(index)
    plan.raws, plan.results = raws, values.copy()  # the caller may change the dict it gets
    return values


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


def changed(raws: list[Any], last: list[Any] | None) -> set[int]:
    """Return the positions whose JSON value is not the same value of the same type as in `last`.

    Equal values of another type (1, 1.0, true) count as changed, and so does every float zero
    (0.0 equals -0.0 but shows otherwise); NaN never equals itself.
    """
    count = range(len(raws))
    if last is None:
        return set(count)
    types, last_types = list(map(type, raws)), list(map(type, last))
    found: set[int] = set()
    if raws != last or types != last_types:
        found.update(compress(count, map(ne, raws, last)))
        found.update(compress(count, map(is_not, types, last_types)))
    if float in types:
        floats = compress(count, map(is_, types, repeat(float)))
        found.update(index for index in floats if not raws[index])
    return found
