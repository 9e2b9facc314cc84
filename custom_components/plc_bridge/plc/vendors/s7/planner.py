"""Pure S7 request planning: merge neighbouring ranges, split, pack into PDU-sized requests.

No sockets here. A `Span` is one item of a multi-variable request (one address spec). Reads
merge the byte ranges the points need into few spans, split spans a PDU cannot carry, and pack
them first-fit-decreasing under three limits: the request PDU (10-byte job header), the reply
PDU (12-byte ACK_DATA header) and the item count (none but the PDU's until a CPU shows one:
items.py).
Merging across a gap trades bytes read in vain for items saved; which trade wins depends on
whether the PDU or the item cap binds, so several gap limits are planned and the plan with the
fewest requests (then the fewest bytes) is kept.
"""

from __future__ import annotations

from bisect import bisect_left
from collections import defaultdict
from collections.abc import Collection, Iterable, Sequence
from dataclasses import dataclass
from itertools import accumulate
from typing import NamedTuple

from .address import AREA_P, COUNTED

DEFAULT_PDU = 480  # what a client assumes before the PLC negotiates (python-snap7's default)
MAX_ITEMS = 255  # the item count is one byte; the PDU binds first (79 specs at PDU 960)
GAPS = (8, 16, 32, 64, 128)  # gap limits tried, in bytes read in vain to save one item
REQUEST_HEADER = 10  # S7 header of a job request
REPLY_HEADER = 12  # S7 header of an ACK_DATA reply (two more bytes: error class and code)
PARAMETER = 2  # function code and item count
SPEC = 12  # one address spec in a request
ITEM_HEADER = 4  # return code, transport size, length of one data item


class Span(NamedTuple):
    """A contiguous range of one area: bytes, or timer/counter numbers (two bytes each).

    A tuple, not a dataclass: a 1,000-point poll hashes and sorts thousands of them.
    """

    area: int
    db: int
    start: int
    length: int

    @property
    def counted(self) -> bool:
        """True for timers and counters (the length counts elements, not bytes)."""
        return self.area in COUNTED

    @property
    def end(self) -> int:
        """First byte (or element) after the span."""
        return self.start + self.length

    @property
    def size(self) -> int:
        """Bytes of data the span carries on the wire."""
        return self.length * (2 if self.counted else 1)

    @property
    def reply_cost(self) -> int:
        """Bytes the span takes in a read reply (with the fill byte after odd data)."""
        return ITEM_HEADER + self.size + self.size % 2

    def overlaps(self, other: Span) -> bool:
        """True when both spans are in the same area and share at least one byte."""
        return (
            (self.area, self.db) == (other.area, other.db)
            and self.start < other.end
            and other.start < self.end
        )


@dataclass(frozen=True, slots=True)
class WriteItem:
    """One item of a multi-variable write: where, how (bit, bytes, T/C words) and the data."""

    span: Span
    data: bytes
    bit: int | None = None  # a BOOL written as a bit (transport size BIT), no read-modify-write

    @property
    def request_cost(self) -> int:
        """Bytes the item takes in a write request: address spec, data header, data, fill."""
        return SPEC + ITEM_HEADER + len(self.data) + len(self.data) % 2


def max_data(pdu_size: int) -> int:
    """The most data bytes one read item can carry in a reply of this PDU size."""
    return pdu_size - REPLY_HEADER - PARAMETER - ITEM_HEADER


def max_write_data(pdu_size: int) -> int:
    """The most data bytes one write item can carry in a request of this PDU size."""
    return pdu_size - REQUEST_HEADER - PARAMETER - SPEC - ITEM_HEADER


def merge(needs: Iterable[Span], *, alone: Collection[Span] = (), max_gap: int = 8) -> list[Span]:
    """Merge overlapping, adjacent and nearby ranges of the same area (gaps <= max_gap bytes).

    Ranges in `alone` (ones that failed inside a merged item before) are never merged, so one
    bad address cannot hide its neighbours. Peripheral I/O only merges ranges that touch: a gap
    there may be a slot without a module.
    """
    merged: list[Span] = []
    for span in sorted(set(needs)):
        last = merged[-1] if merged else None
        gap = (span.start - (last.end if last else 0)) * (2 if span.counted else 1)
        if (
            last is not None
            and span not in alone
            and last not in alone
            and (last.area, last.db) == (span.area, span.db)
            and gap <= (0 if span.area == AREA_P else max_gap)
        ):
            merged[-1] = Span(last.area, last.db, last.start, max(last.end, span.end) - last.start)
        else:
            merged.append(span)
    return merged


def split(span: Span, limit: int) -> list[Span]:
    """Cut a span into pieces of at most `limit` data bytes (whole elements for T/C)."""
    step = limit // 2 if span.counted else limit
    if step < 1:
        raise ValueError(f"a PDU of this size cannot carry one item ({limit} bytes of data)")
    return [
        Span(span.area, span.db, start, min(step, span.end - start))
        for start in range(span.start, span.end, step)
    ]


def pack(spans: Iterable[Span], pdu_size: int, max_items: int = MAX_ITEMS) -> list[list[Span]]:
    """Pack read items first-fit-decreasing into requests within both PDUs and the item cap."""
    budget = pdu_size - REPLY_HEADER - PARAMETER
    specs = (pdu_size - REQUEST_HEADER - PARAMETER) // SPEC  # address specs a request holds
    requests: list[list[Span]] = []
    used: list[int] = []
    for span in sorted(spans, key=lambda item: (-item.reply_cost, item)):
        for index, request in enumerate(requests):
            if len(request) < min(max_items, specs) and used[index] + span.reply_cost <= budget:
                request.append(span)
                used[index] += span.reply_cost
                break
        else:
            requests.append([span])
            used.append(span.reply_cost)
    return [sorted(request) for request in requests]


def plan_reads(
    needs: Iterable[Span],
    pdu_size: int = DEFAULT_PDU,
    *,
    alone: Collection[Span] = (),
    max_items: int = MAX_ITEMS,
) -> list[list[Span]]:
    """Plan the read requests of one poll: merge, split to the PDU, pack; the best of GAPS."""
    needs, limit = set(needs), max_data(pdu_size)
    best: list[list[Span]] = []
    best_cost = (0, 0)
    for gap in GAPS:
        merged = merge(needs, alone=alone, max_gap=gap)
        plan = pack([piece for span in merged for piece in split(span, limit)], pdu_size, max_items)
        cost = (len(plan), sum(span.reply_cost for request in plan for span in request))
        if not best or cost < best_cost:
            best, best_cost = plan, cost
    return best


def assemble(need: Span, got: Sequence[tuple[Span, bytes | int]]) -> bytes | int:
    """Return the bytes of `need` cut from the items read, or the code of a failed item."""
    if len(got) == 1:  # the usual case, made quick: one item holds the whole need
        span, data = got[0]
        inside = span[:2] == need[:2] and span.start <= need.start and need.end <= span.end
        if inside and isinstance(data, bytes):
            unit = 2 if need.counted else 1
            return data[(need.start - span.start) * unit : (need.end - span.start) * unit]
    unit = 2 if need.counted else 1
    buffer, covered = bytearray(need.size), bytearray(need.length)
    code: int | None = None
    for span, item in got:
        if not span.overlaps(need):
            continue
        if isinstance(item, int):
            code = item if code is None else code
            continue
        low, high = max(span.start, need.start), min(span.end, need.end)
        part = item[(low - span.start) * unit : (high - span.start) * unit]
        buffer[(low - need.start) * unit : (high - need.start) * unit] = part
        covered[low - need.start : high - need.start] = b"\x01" * (high - low)
    if covered.count(0) == 0:
        return bytes(buffer)
    if code is not None:
        return code
    raise ValueError(f"no item read covers all of {need}")


def locate(needs: Iterable[Span], spans: Sequence[Span]) -> dict[Span, list[int]]:
    """Return for every need the positions of the spans holding part of it (by bisection)."""
    order: dict[tuple[int, int], list[int]] = defaultdict(list)
    for position in sorted(range(len(spans)), key=spans.__getitem__):
        order[spans[position].area, spans[position].db].append(position)
    starts, reach = {}, {}
    for key, positions in order.items():
        starts[key] = [spans[position].start for position in positions]
        reach[key] = list(accumulate((spans[position].end for position in positions), max))
    found: dict[Span, list[int]] = {}
    for need in needs:
        key = (need.area, need.db)
        positions = order.get(key, [])
        high = low = bisect_left(starts.get(key, []), need.end)
        while low > 0 and reach[key][low - 1] > need.start:
            low -= 1
        found[need] = [p for p in positions[low:high] if spans[p].end > need.start]
    return found


def extract(
    needs: Iterable[Span], got: Sequence[tuple[Span, bytes | int]]
) -> dict[Span, bytes | int]:
    """Return `assemble` for every need from the items read."""
    needs = list(needs)
    where = locate(needs, [span for span, _ in got])
    return {need: assemble(need, [got[position] for position in where[need]]) for need in needs}


def failed_needs(
    needs: Iterable[Span],
    got: Sequence[tuple[Span, bytes | int]],
    where: dict[Span, list[int]] | None = None,
) -> set[Span]:
    """The needs that shared a failed item with other needs: each must be read on its own.

    `where` is `locate(needs, spans read)` where the caller has it (linear, not needs x items).
    """
    if where is None:
        needs = list(needs)
        where = locate(needs, [span for span, _ in got])
    sharing: dict[int, list[Span]] = defaultdict(list)
    for need, positions in where.items():
        for position in positions:
            if isinstance(got[position][1], int):
                sharing[position].append(need)
    return {need for inside in sharing.values() if len(inside) > 1 for need in inside}


def plan_writes(
    items: Iterable[WriteItem], pdu_size: int, max_items: int = MAX_ITEMS
) -> list[list[WriteItem]]:
    """Pack write items in order into requests within the PDU and the item cap."""
    budget = pdu_size - REQUEST_HEADER - PARAMETER
    requests: list[list[WriteItem]] = []
    used = budget + 1
    for item in items:
        if not requests or len(requests[-1]) >= max_items or used + item.request_cost > budget:
            requests.append([])
            used = 0
        requests[-1].append(item)
        used += item.request_cost
    return requests


def write_pieces(span: Span, data: bytes, pdu_size: int) -> list[WriteItem]:
    """Cut the data of one byte or T/C write into items a request of this PDU can carry."""
    unit = 2 if span.counted else 1
    return [
        WriteItem(piece, data[(piece.start - span.start) * unit : (piece.end - span.start) * unit])
        for piece in split(span, max_write_data(pdu_size))
    ]
