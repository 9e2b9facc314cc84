"""S7 writes: STRING lengths checked against the PLC's own headers, then multi-variable requests.

An S7 STRING starts with two bytes: the maximum length the PLC declared, then the current
length (a WSTRING: two words). Neither the point's STRING (254) nor its STRING[n] is trusted for
a write, since text longer than the PLC's maximum would run into the next variable: the headers
of every STRING of a write are read first (one request for all, one round trip more), longer
text is refused, and only the current length and the characters are written.
"""

from __future__ import annotations

from collections.abc import Mapping
from datetime import tzinfo

from ...errors import PlcAddressError, PlcError, PlcValueError, PlcWriteRefusedError
from ...types import Point, PointResult, Value
from .address import STRING_MAX, WSTRING_MAX, Variable
from .codec import write_items
from .items import ItemLimit, read_plan, send_all
from .link import S7Link, S7RequestError
from .planner import Span, WriteItem, extract, plan_reads, plan_writes
from .protocol import OK, item_error


def _write_refused(err: S7RequestError) -> PlcWriteRefusedError:
    """Return the error of a write job the PLC refused whatever its size."""
    return PlcWriteRefusedError(f"the PLC refused the write: {err}")


async def write_values(
    link: S7Link,
    values: Mapping[Point, tuple[Variable, Value]],
    zone: tzinfo,
    items: ItemLimit,
) -> dict[Point, PointResult]:
    """Write checked values in as few requests as the PDU allows; a result per point."""
    results: dict[Point, PointResult] = {}
    strings = [found for found, _ in values.values() if found.string_length]
    limits = await _string_limits(link, strings, items) if strings else {}
    flat: list[tuple[Point, WriteItem]] = []
    for point, (found, value) in values.items():
        try:
            if found.string_length:
                _check_length(found, value, limits[found])
            pieces = write_items(found, value, zone, link.pdu_size)
        except PlcError as err:
            results[point] = PointResult(error=err)
            continue
        flat += [(point, piece) for piece in pieces]
    codes: dict[Point, list[int]] = {point: [] for point, _ in flat}
    done = 0
    for request in plan_writes([item for _, item in flat], link.pdu_size, items.count):
        for code in await send_all(link.write, request, items, _write_refused):
            assert isinstance(code, int)
            codes[flat[done][0]].append(code)
            done += 1
    for point, point_codes in codes.items():
        bad = next((code for code in point_codes if code != OK), None)
        if bad is None:
            results[point] = PointResult(value=values[point][1])
        else:
            results[point] = PointResult(error=item_error(bad, values[point][0].text, write=True))
    return results


async def _string_limits(
    link: S7Link, strings: list[Variable], items: ItemLimit
) -> dict[Variable, int | PlcError]:
    """Return the maximum length each STRING's header declares, or why it could not be read."""
    headers = {
        found: Span(found.area, found.db, found.start, found.header_size) for found in strings
    }
    needs = set(headers.values())
    plan = plan_reads(needs, link.pdu_size, alone=needs, max_items=items.count)
    got = extract(needs, await read_plan(link, plan, items))
    limits: dict[Variable, int | PlcError] = {}
    for found, span in headers.items():
        header = got[span]
        if isinstance(header, int):
            limits[found] = item_error(header, found.text)
            continue
        half = found.header_size // 2
        maximum = int.from_bytes(header[:half], "big")
        if not 0 < maximum <= (WSTRING_MAX if found.wide else STRING_MAX) or (
            int.from_bytes(header[half:], "big") > maximum
        ):
            limits[found] = PlcAddressError(
                f"{found.text} holds no S7 {'W' if found.wide else ''}STRING: its header reads "
                f"{header.hex(' ')} (maximum length, then current length)"
            )
        else:
            limits[found] = maximum
    return limits


def _check_length(found: Variable, value: Value, limit: int | PlcError) -> None:
    """Raise the header's error, or PlcValueError for text longer than the PLC's maximum."""
    if isinstance(limit, PlcError):
        raise limit
    if not isinstance(value, str):
        return
    length = len(value.encode("utf-16-be")) // 2 if found.wide else len(value)
    if length > limit:
        raise PlcValueError(
            f"{found.text} is a {'W' if found.wide else ''}STRING[{limit}] in the PLC: "
            f"{length} characters do not fit"
        )
