"""One S7 poll's reads: points resolved once, ranges planned once, failed merges re-read alone."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from datetime import tzinfo

from ...errors import PlcAddressError, PlcProtocolError
from ...types import Point, PointResult
from .address import Variable
from .codec import decode, span_of
from .items import ItemLimit, read_plan
from .link import S7Link
from .planner import Span, assemble, extract, failed_needs, locate, plan_reads
from .protocol import item_error

type Fetched = dict[Span, bytes | int]


@dataclass(frozen=True, slots=True)
class Layout:
    """The points of a poll resolved: errors of invalid ones, variables, ranges to read."""

    points: tuple[Point, ...]
    errors: dict[Point, PointResult]
    groups: list[tuple[Variable, Span, list[Point]]]  # a variable, its range, its points
    needs: frozenset[Span]


def outcome(found: Variable, item: bytes | int, zone: tzinfo) -> PointResult:
    """Return one point's value, or its own error."""
    if isinstance(item, int):
        return PointResult(error=item_error(item, found.text))
    try:
        return PointResult(value=decode(found, item, zone))
    except PlcProtocolError as err:
        return PointResult(error=err)


class Reader:
    """Plans and reads the points of a poll; a coordinator asks the same ones each time: kept."""

    def __init__(self, resolve: Callable[[Point], Variable], limit: ItemLimit) -> None:
        """Resolve points with `resolve` (raising PlcAddressError for invalid ones)."""
        self._resolve = resolve
        self._limit = limit  # items a job: the client's, shared with writes
        self._alone: set[Span] = set()  # ranges that failed inside a merged item: read alone
        self._last_layout: Layout | None = None
        self._last_plan: tuple[object, list[list[Span]], dict[Span, list[int]]] | None = None

    def forget(self) -> None:
        """Forget what a previous link taught (a new one may be another CPU or program)."""
        self._alone.clear()

    def layout(self, points: Sequence[Point], *, keep: bool = True) -> Layout:
        """Resolve the points of a poll, or return the last layout for the same points.

        An on-demand read (`keep` false) is resolved on its own and leaves the poll's layout.
        """
        if not keep or self._last_layout is None or self._last_layout.points != tuple(points):
            errors: dict[Point, PointResult] = {}
            wanted: dict[Variable, list[Point]] = {}
            for point in points:
                try:
                    wanted.setdefault(self._resolve(point), []).append(point)
                except PlcAddressError as err:
                    errors[point] = PointResult(error=err)
            groups = [(found, span_of(found), group) for found, group in wanted.items()]
            needs = frozenset(need for _, need, _ in groups)
            layout = Layout(tuple(points), errors, groups, needs)
            if not keep:
                return layout
            self._last_layout = layout
        return self._last_layout

    async def fetch(self, link: S7Link, needs: frozenset[Span]) -> Fetched:
        """Read the ranges; re-read alone (once) the ones that shared a failed item.

        The ones that fail alone stay alone in later polls; the others merge again.
        """
        plan, where = self._plan(needs, link.pdu_size)
        got = await read_plan(link, plan, self._limit)
        fetched = {need: assemble(need, [got[p] for p in where[need]]) for need in needs}
        retry = failed_needs(needs, got, where) - self._alone
        if retry:
            again = plan_reads(retry, link.pdu_size, alone=retry, max_items=self._limit.count)
            fetched |= extract(retry, await read_plan(link, again, self._limit))
            self._alone |= {need for need in retry if isinstance(fetched[need], int)}
        return fetched

    def _plan(
        self, needs: frozenset[Span], pdu_size: int
    ) -> tuple[list[list[Span]], dict[Span, list[int]]]:
        """Plan the reads and where each need lies in them; kept while nothing changes."""
        key = (needs, pdu_size, frozenset(self._alone), self._limit.count)
        if self._last_plan is None or self._last_plan[0] != key:
            plan = plan_reads(needs, pdu_size, alone=self._alone, max_items=self._limit.count)
            where = locate(needs, [span for request in plan for span in request])
            self._last_plan = (key, plan, where)
        return self._last_plan[1], self._last_plan[2]
