"""One S7 poll's reads: points resolved once, ranges planned once, failed merges re-read alone."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from datetime import tzinfo
import logging

from ...errors import PlcAddressError, PlcProtocolError
from ...types import Point, PointResult
from .address import Variable
from .codec import decode, span_of
from .link import S7Link, S7RequestError
from .planner import MAX_ITEMS, Span, assemble, extract, failed_needs, locate, plan_reads
from .protocol import item_error

type Fetched = dict[Span, bytes | int]


@dataclass(frozen=True, slots=True)
class Layout:
    """The points of a poll resolved: errors of invalid ones, variables, ranges to read."""

    points: tuple[Point, ...]
    errors: dict[Point, PointResult]
    groups: list[tuple[Variable, Span, list[Point]]]  # a variable, its range, its points
    needs: frozenset[Span]


async def read_plan(link: S7Link, plan: list[list[Span]]) -> list[tuple[Span, bytes | int]]:
    """Send the planned read requests; pair each item with its data or return code."""
    got: list[tuple[Span, bytes | int]] = []
    for request in plan:
        try:
            items = await link.read(request)
        except S7RequestError as err:
            raise PlcProtocolError(f"the PLC refused the read: {err}{refusal_hint(err)}") from err
        for span, item in zip(request, items, strict=True):
            if isinstance(item, bytes) and len(item) != span.size:
                raise PlcProtocolError(
                    f"the PLC answered {len(item)} bytes for an item of {span.size}"
                )
            got.append((span, item))
    return got


_LOGGER = logging.getLogger(__name__)
WRONG_FRAMES = 0x8500
"""The header error a CPU answers a job it cannot take in one PDU with (too many items)."""
FUNCTION_NOT_AVAILABLE = 0x8104
"""The header error an S7-1200/1500 answers every read and write job with while PUT/GET access is
not permitted. The protocol document names no error classes; this is the CPU's behaviour as
public S7 clients report it (python-snap7 and Snap7: "CPU : Function not available")."""


def refusal_hint(err: S7RequestError) -> str:
    """Return the advice for the refusal that means PUT/GET is off, and for no other."""
    if err.code == FUNCTION_NOT_AVAILABLE:
        return " (an S7-1200/1500 must permit PUT/GET access)"
    return ""


def too_many_items(err: PlcProtocolError) -> bool:
    """True when the PLC refused a read job as too big for it (not for what it asked)."""
    cause = err.__cause__
    return isinstance(cause, S7RequestError) and cause.code == WRONG_FRAMES


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

    def __init__(self, resolve: Callable[[Point], Variable]) -> None:
        """Resolve points with `resolve` (raising PlcAddressError for invalid ones)."""
        self._resolve = resolve
        self._alone: set[Span] = set()  # ranges that failed inside a merged item: read alone
        self._last_layout: Layout | None = None
        self._last_plan: tuple[object, list[list[Span]], dict[Span, list[int]]] | None = None
        self._max_items = MAX_ITEMS  # lowered, and kept, when the CPU refuses as many

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
        while True:
            plan, where = self._plan(needs, link.pdu_size)
            try:
                got = await read_plan(link, plan)
                break
            except PlcProtocolError as err:
                largest = max(len(request) for request in plan)
                if not too_many_items(err) or largest <= 1:
                    raise
                # A CPU that takes fewer items than the usual cap: halve and keep the limit.
                self._max_items = largest // 2
                _LOGGER.info(
                    "The PLC refused %d items in one request; reading at most %d from now on",
                    largest,
                    self._max_items,
                )
        fetched = {need: assemble(need, [got[p] for p in where[need]]) for need in needs}
        retry = failed_needs(needs, got) - self._alone
        if retry:
            again = await read_plan(
                link, plan_reads(retry, link.pdu_size, alone=retry, max_items=self._max_items)
            )
            fetched |= extract(retry, again)
            self._alone |= {need for need in retry if isinstance(fetched[need], int)}
        return fetched

    def _plan(
        self, needs: frozenset[Span], pdu_size: int
    ) -> tuple[list[list[Span]], dict[Span, list[int]]]:
        """Plan the reads and where each need lies in them; kept while nothing changes."""
        key = (needs, pdu_size, frozenset(self._alone), self._max_items)
        if self._last_plan is None or self._last_plan[0] != key:
            plan = plan_reads(needs, pdu_size, alone=self._alone, max_items=self._max_items)
            where = locate(needs, [span for request in plan for span in request])
            self._last_plan = (key, plan, where)
        return self._last_plan[1], self._last_plan[2]
