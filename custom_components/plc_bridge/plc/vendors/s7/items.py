"""How many items one S7 job carries: as many as the PDU holds, fewer once the CPU shows its limit.

The protocol document gives the item count one byte and names no limit; S7 CPUs take what the
PDU carries (S7-1500 users read and write 36 and more a job), Snap7-based servers 20. A CPU that
takes fewer shows it in one of three ways (simulators/s7/READINGS.md), each teaching a smaller
count that is kept until the link is replaced:

- It refuses the job (a header error). Unless a job that large already worked on this link, its
  first item is asked alone: refused too, the refusal is not about the count (PUT/GET off) and
  fails as it is; otherwise the count is bisected between the largest job that worked and the
  smallest refused (30 refused by a CPU taking 5: 15, 8, 4, 6, 5; a few jobs more, once).
- It answers fewer items than asked. None is used (no answer says which items it left out): the
  count becomes the number answered and the job is sent again in parts of that size.
- It answers the items past its limit with an error code. A failed run at the end of a job is
  sent again in parts as large as the items before it; where one then succeeds the count was the
  cause and is kept, the others keep their codes (and are not asked again on this link).
"""

from __future__ import annotations

from collections.abc import Awaitable, Callable, Sequence
from dataclasses import dataclass, field
import logging

from ...errors import PlcError, PlcProtocolError
from .link import S7Link, S7RequestError
from .planner import MAX_ITEMS, Span
from .protocol import OK, ShortAnswer

_LOGGER = logging.getLogger(__name__)
FUNCTION_NOT_AVAILABLE = 0x8104
"""The header error an S7-1200/1500 answers every read and write job with while PUT/GET access is
not permitted. The protocol document names no error classes; this is the CPU's behaviour as
public S7 clients report it (python-snap7 and Snap7: "CPU : Function not available")."""

type Item = bytes | int  # an item's data (reads), or its return code
type Send[T] = Callable[[list[T]], Awaitable[Sequence[Item]]]


@dataclass(slots=True)
class ItemLimit:
    """The most items a job may carry on this link, what worked, and items known to fail."""

    count: int = MAX_ITEMS
    proven: int = 0  # the most items one job carried on this link
    clean: int = 0  # the most items of a job whose last item was answered with data
    refused: int = MAX_ITEMS + 1  # the fewest items a job was refused with on this link
    failing: set[object] = field(default_factory=set)  # failed in a job short enough: no retry

    def forget(self) -> None:
        """A new link, maybe another CPU: start again from the PDU's count."""
        self.count, self.proven, self.clean, self.refused = MAX_ITEMS, 0, 0, MAX_ITEMS + 1
        self.failing.clear()

    def worked(self, count: int) -> None:
        """A job of `count` items was answered: try halfway to the smallest refused next."""
        self.proven = max(self.proven, count)
        self.count = max(self.count, (self.proven + self.refused) // 2)

    def refuse(self, count: int) -> None:
        """A job of `count` items (more than ever worked) was refused: halve towards what did."""
        self.refused = min(self.refused, count)
        self.count = max(self.proven, (self.proven + count) // 2)
        _LOGGER.debug("The PLC refused %d items a job; trying %d", count, self.count)

    def cut(self, count: int) -> None:
        """The PLC showed it takes `count` items a job (a short answer, a failed run)."""
        self.count, self.refused = count, count + 1
        self.proven, self.clean = min(self.proven, count), min(self.clean, count)
        _LOGGER.debug("The PLC takes %d items a job", count)


def refusal_hint(err: S7RequestError) -> str:
    """Return the advice for the refusal that means PUT/GET is off, and for no other."""
    if err.code == FUNCTION_NOT_AVAILABLE:
        return " (an S7-1200/1500 must permit PUT/GET access)"
    return ""


def read_refused(err: S7RequestError) -> PlcError:
    """Return the error of a read job the PLC refused whatever its size."""
    return PlcProtocolError(f"the PLC refused the read: {err}{refusal_hint(err)}")


def failed(item: Item) -> bool:
    """True for an item answered with an error code (0xFF is a write's success)."""
    return isinstance(item, int) and item != OK


async def send_all[T](
    send: Send[T],
    entries: Sequence[T],
    limit: ItemLimit,
    refused: Callable[[S7RequestError], PlcError],
    cap: int | None = None,
) -> list[Item]:
    """Send the entries in jobs of at most `limit.count` (and `cap`) items; answers in order."""
    answers: list[Item] = []
    start = 0
    while start < len(entries):
        part = list(entries[start : start + min(limit.count, cap or limit.count)])
        answers += await _send_part(send, part, limit, refused)
        start += len(part)
    return answers


async def _send_part[T](
    send: Send[T], part: list[T], limit: ItemLimit, refused: Callable[[S7RequestError], PlcError]
) -> list[Item]:
    """Send one job; on a refusal or a short answer learn the count and send the rest again."""
    try:
        answers = list(await send(part))
    except S7RequestError as err:
        if len(part) <= max(limit.proven, 1) or not err.code:  # no code: a garbled answer
            raise refused(err) from err
        first: list[Item] = []
        if not limit.proven:  # PUT/GET off refuses one item too: ask one first
            try:
                first = list(await send(part[:1]))
            except S7RequestError:
                raise refused(err) from err
            limit.proven = 1
        limit.refuse(len(part))
        return first + await send_all(send, part[len(first) :], limit, refused)
    except ShortAnswer as short:
        if not short.answered:
            raise PlcProtocolError(f"the PLC answered none of {len(part)} items") from None
        limit.cut(short.answered)
        return await send_all(send, part, limit, refused)
    limit.worked(len(part))
    if answers and not failed(answers[-1]):
        limit.clean = max(limit.clean, len(part))
    return await _failed_run(send, part, answers, limit, refused)


async def _failed_run[T](
    send: Send[T],
    part: list[T],
    answers: list[Item],
    limit: ItemLimit,
    refused: Callable[[S7RequestError], PlcError],
) -> list[Item]:
    """Send again the run of failed items that ends a job, in parts as long as what precedes it.

    Not where a job as long already ended in an answered item, nor for items known to fail.
    """
    if len(part) <= limit.clean or not failed(answers[-1]):
        return answers
    start = len(answers)
    while start > 0 and failed(answers[start - 1]):
        start -= 1
    tail = part[start:]
    if not start or all(entry in limit.failing for entry in tail):
        return answers
    again = await send_all(send, tail, limit, refused, cap=start)
    if any(not failed(answer) for answer in again):
        limit.cut(start)
    limit.failing.update(entry for entry, answer in zip(tail, again, strict=True) if failed(answer))
    return answers[:start] + again


async def read_plan(
    link: S7Link, plan: list[list[Span]], limit: ItemLimit
) -> list[tuple[Span, bytes | int]]:
    """Send the planned read requests; pair each item with its data or return code."""
    got: list[tuple[Span, bytes | int]] = []
    for request in plan:
        items = await send_all(link.read, request, limit, read_refused)
        for span, item in zip(request, items, strict=True):
            if isinstance(item, bytes) and len(item) != span.size:
                raise PlcProtocolError(
                    f"the PLC answered {len(item)} bytes for an item of {span.size}"
                )
            got.append((span, item))
    return got
