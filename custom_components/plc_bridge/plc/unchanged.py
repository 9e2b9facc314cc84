"""Values a poll finds unchanged: a vendor reuses their last results instead of decoding again.

Decoding the same JSON value for the same type (and zone) gives the same value, so a poll of
10,000 values need run no Python code per value where nothing changed: the values are compared
with the last poll's a list at a time.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from itertools import compress, repeat
from operator import is_, is_not, ne
from typing import Any

from .types import Point, PointResult


@dataclass(slots=True)
class LastResults:
    """A poll's JSON values and results by position, reused where the same value comes again."""

    raws: list[Any] | None = None
    results: dict[Point, PointResult] = field(default_factory=dict)
    stale: set[int] = field(default_factory=set)  # positions whose last result was an error

    def update(
        self,
        points: Sequence[Point],
        raws: list[Any],
        first: Mapping[Point, PointResult],
        result_of: Callable[[int, Any], PointResult],
        also: Iterable[int] = (),
    ) -> dict[Point, PointResult]:
        """Return every point's result: the last one where its value is the same.

        The others are `result_of(position, raw)`; `first` holds the results of points no value
        can change (bad addresses); `also`: positions to work out again whatever their value.
        """
        todo = changed(raws, self.raws) | self.stale
        todo.update(also)
        values = self.results.copy() if self.raws is not None else dict(first)
        for index in sorted(todo):
            result = result_of(index, raws[index])
            values[points[index]] = result
            if result.ok:
                self.stale.discard(index)
            else:
                self.stale.add(index)
        self.raws, self.results = raws, values.copy()  # the caller may change the dict it gets
        return values


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
