"""Which writes a PLC's layout allows: never-writable addresses, read-only data however spelled.

A write is refused where its address can never be written (an input) and where what it writes
touches any data of a read-only point of the same PLC. The forms, tables and the pasted file
refuse such a layout when it is made (`layout_conflicts`); runtime/write_guard.py refuses such a
write when it is sent, with the same rule.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

from ..const import CONF_ADDRESS, CONF_DATA_TYPE, CONF_READ_ONLY
from ..plc import Footprint, PlcClient, PlcError, Point
from .composite import written

type Client = type[PlcClient] | PlcClient


@dataclass(frozen=True, slots=True)
class Conflict:
    """Why a point may not be written: an error key, the point and the read-only one it meets."""

    key: str
    point: Point
    other: Point | None = None

    @property
    def placeholders(self) -> dict[str, str]:
        """The message's placeholders: the point's address, and the read-only point's."""
        found = {"address": self.point.address}
        if self.other is not None:
            found["point"] = self.other.address
        return found


class ReadOnlyPoints:
    """The read-only points of one PLC, by what they cover: what a write of a point meets."""

    def __init__(self, client: Client, read_only: Iterable[Point]) -> None:
        """Keep the read-only points; what they cover is asked at each check (reads tell more)."""
        self._client = client
        self._read_only = list(dict.fromkeys(read_only))

    def conflict(self, point: Point) -> Conflict | None:
        """Return why a write of the (validated) point would meet read-only data, if it would.

        The point itself (another spelling of it), data it covers, or data its vendor writes
        with it (a SoftPLC bit's whole word): each with its own reason.
        """
        covers = _footprint(self._client, point)
        writes = _footprint(self._client, point, write=True)
        for other in self._read_only:
            footprint = _footprint(self._client, other, read=True)
            if other == point or (covers is not None and covers == footprint):
                return Conflict("read_only", point)
            if footprint is None:
                continue
            if covers is not None and covers.overlaps(footprint):
                return Conflict("covers_read_only", point, other)
            if writes is not None and writes.overlaps(footprint):
                return Conflict("writes_read_only", point, other)
        return None


def layout_conflicts(
    client: Client, points: Iterable[Mapping[str, Any]], new: Iterable[Mapping[str, Any]]
) -> list[tuple[Mapping[str, Any], Conflict]]:
    """Return the new points (stored data) in a layout their entities cannot write.

    A new point its entity writes (a control or a written part, not read only) whose write
    meets a read-only point of the PLC (`points`, the others) or of `new` is named with that
    conflict (so a command, not the state beside it); a new read-only point that an existing
    written point's write meets is named with the written one's conflict. A point only shown,
    or at an address no write reaches (an input), is left to the write guard; unparsable
    points are the parser's to refuse.
    """
    fresh, known = list(new), list(points)
    locked = [data for data in (*known, *fresh) if data.get(CONF_READ_ONLY)]
    guard = ReadOnlyPoints(client, [_point(client, data) for data in locked])
    writers = [point for data in known if (point := _writer(client, data)) is not None]
    found: list[tuple[Mapping[str, Any], Conflict]] = []
    for data in fresh:
        if data.get(CONF_READ_ONLY):
            alone = ReadOnlyPoints(client, [_point(client, data)])
            hit = next((c for other in writers if (c := alone.conflict(other))), None)
        elif (point := _writer(client, data)) is not None:
            hit = guard.conflict(point)
        else:
            hit = None
        if hit is not None:
            found.append((data, hit))
    return found


def _writer(client: Client, data: Mapping[str, Any]) -> Point | None:
    """Return a stored point its entity writes; None if read only, only shown or at an input."""
    if data.get(CONF_READ_ONLY) or not written(data):
        return None
    point = _point(client, data)
    return point if writable(client, point) else None


def _point(client: Client, data: Mapping[str, Any]) -> Point:
    """Return a stored point as its vendor spells it (as typed where the parser refuses it)."""
    point = Point(str(data[CONF_ADDRESS]), str(data[CONF_DATA_TYPE]))
    try:
        return client.validate_point(point)
    except PlcError:
        return point


def _footprint(
    client: Client, point: Point, *, write: bool = False, read: bool = False
) -> Footprint | None:
    """What the point covers (or a write of it changes); None for one its vendor cannot parse.

    `read`: as the connected client last read it (a read-only S7-200 SMART string its length).
    """
    try:
        if read and isinstance(client, PlcClient):
            return client.covers(point)
        return client.write_footprint(point) if write else client.footprint(point)
    except PlcError:
        return None


def writable(client: Client, point: Point) -> bool:
    """False for an address no write can ever reach; an unparsable one is the parser's to refuse."""
    try:
        return client.address_writable(point)
    except PlcError:
        return True
