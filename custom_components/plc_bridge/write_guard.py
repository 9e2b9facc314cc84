"""The one check every write passes, from an entity or the write action, before anything is sent.

A write is refused where its address can never be written (an input) and where it covers any
data of a read-only point of the same PLC, however it is spelled: `VB100` or `VW100 unsigned`
against a read-only `VW100`, another case of a TecoApi name, an element of a read-only array.
"""

from __future__ import annotations

from collections.abc import Iterable

from homeassistant.exceptions import ServiceValidationError

from .const import DOMAIN
from .plc import Footprint, PlcClient, PlcError, Point


class WriteGuard:
    """The read-only points of one PLC, by what they cover, and the check of a write."""

    def __init__(self, client: type[PlcClient] | PlcClient, read_only: Iterable[Point]) -> None:
        """Keep the read-only points; what they cover is asked at each check (reads tell more)."""
        self._client = client
        self._read_only = list(dict.fromkeys(read_only))

    def check(self, point: Point) -> None:
        """Refuse the write of a (validated) point; raise ServiceValidationError, send nothing."""
        if not _writable(self._client, point):
            raise _refused("address_not_writable", point)
        covers = _footprint(self._client, point)
        for other in self._read_only:
            footprint = _footprint(self._client, other, read=True)
            if other == point or (covers is not None and covers == footprint):
                raise _refused("read_only", point)
            if covers is not None and footprint is not None and covers.overlaps(footprint):
                raise _refused("covers_read_only", point, other)


def _footprint(
    client: type[PlcClient] | PlcClient, point: Point, *, read: bool = False
) -> Footprint | None:
    """What the point covers, or None for one its vendor cannot parse (compared as typed).

    `read`: as the connected client last read it (a read-only S7-200 SMART string its length).
    """
    try:
        if read and isinstance(client, PlcClient):
            return client.covers(point)
        return client.footprint(point)
    except PlcError:
        return None


def _writable(client: type[PlcClient] | PlcClient, point: Point) -> bool:
    """False for an address no write can ever reach; an unparsable one is the parser's to refuse."""
    try:
        return client.address_writable(point)
    except PlcError:
        return True


def _refused(key: str, point: Point, other: Point | None = None) -> ServiceValidationError:
    """Return the translated refusal of a write."""
    placeholders = {"address": point.address}
    if other is not None:
        placeholders["point"] = other.address
    return ServiceValidationError(
        translation_domain=DOMAIN, translation_key=key, translation_placeholders=placeholders
    )
