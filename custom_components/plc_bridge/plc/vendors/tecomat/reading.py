"""What GetObject requests gave (values, errors, variables found unknown), and points' results."""

from __future__ import annotations

from dataclasses import dataclass, field
from datetime import tzinfo
from itertools import repeat
from typing import Any

from ...errors import PlcAddressError, PlcError, PlcProtocolError
from ...types import Point, PointResult
from ...unchanged import LastResults
from .codec import decode
from .paths import VariablePath

_ABSENT = object()  # a path with no value in the reading


@dataclass(frozen=True, slots=True)
class Gone:
    """A variable the PLC does not know (400.005): its path, and the name the PLC's answer gave."""

    path: VariablePath
    name: str

    def error(self, path: VariablePath) -> PlcAddressError:
        """Return the error of a path that is or lies inside this variable."""
        return PlcAddressError(
            f"{path.text}: the PLC does not know this variable "
            f"(400.005: '{self.name}' is not found)"
        )


@dataclass(slots=True)
class Reading:
    """What GetObject requests gave: raw values and per-path errors, by path key."""

    found: dict[str, Any] = field(default_factory=dict)
    failed: dict[str, PlcError] = field(default_factory=dict)
    gone: dict[str, Gone] = field(default_factory=dict)  # unknown variables (400.005), by key
    too_big: set[str] = field(default_factory=set)  # alone, more items than one answer holds
    answers: list[tuple[Any, list[VariablePath]]] = field(default_factory=list)  # raw, with asked
    # Arrays whose list answer placed nothing (first index unknown), with its lengths, by key.
    lists: dict[str, tuple[VariablePath, tuple[int, ...]]] = field(default_factory=dict)

    def merge(self, other: Reading) -> None:
        """Take in another reading's results."""
        self.found.update(other.found)
        self.failed.update(other.failed)
        self.gone.update(other.gone)
        self.too_big |= other.too_big
        self.answers += other.answers
        self.lists |= other.lists


def gone_for(path: VariablePath, gone: dict[str, Gone]) -> Gone | None:
    """Return the unknown variable a path is or lies inside."""
    for entry in gone.values():
        if under(path, entry.path):
            return entry
    return None


def under(path: VariablePath, prefix: VariablePath) -> bool:
    """True when path is prefix or lies inside it (compared as the PLC does, ignoring case)."""
    return path.key == prefix.key or path.key.startswith((prefix.key + ".", prefix.key + "["))


@dataclass(slots=True)
class Plan:
    """A poll's points parsed once: each path and type, the distinct paths, the last results."""

    points: tuple[Point, ...]
    errors: dict[Point, PointResult] = field(default_factory=dict)  # points that do not parse
    wanted: list[tuple[Point, VariablePath, str]] = field(default_factory=list)
    targets: list[Point] = field(default_factory=list)  # by position in `wanted`
    keys: list[str] = field(default_factory=list)  # each wanted point's path key
    paths: dict[str, VariablePath] = field(default_factory=dict)  # the first spelling of each
    last: LastResults = field(default_factory=LastResults)

    def want(self, point: Point, path: VariablePath, kind: str) -> None:
        """Add a point whose path and type parsed."""
        self.wanted.append((point, path, kind))
        self.targets.append(point)
        self.keys.append(path.key)
        self.paths.setdefault(path.key, path)  # names are case-insensitive


def results(reading: Reading, plan: Plan, zone: tzinfo) -> dict[Point, PointResult]:
    """Return the plan's results from a reading; a value sent as at the last poll keeps its own."""
    found, failed, wanted = reading.found, reading.failed, plan.wanted

    def result_of(index: int, raw: Any) -> PointResult:
        """Decode one point's value, or give its error."""
        _point, path, kind = wanted[index]
        if raw is _ABSENT:
            return PointResult(error=failed[path.key])
        try:
            return PointResult(value=decode(kind, raw, zone, path.text))
        except PlcProtocolError as err:
            return PointResult(error=err)

    raws = list(map(found.get, plan.keys, repeat(_ABSENT)))
    return plan.last.update(plan.targets, raws, plan.errors, result_of)
