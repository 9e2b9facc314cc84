"""The one check every write passes, from an entity or the write action, before anything is sent.

A write is refused where its address can never be written (an input) and where what it writes
touches any data of a read-only point of the same PLC, however it is spelled: `VB100` or
`VW100 unsigned` against a read-only `VW100`, another case of a TecoApi name, an element of a
read-only array, a SoftPLC bit whose word (written whole) holds a read-only bit. The forms and
tables refuse such a layout when it is made, with the same check (`layout_conflicts`).
"""

from __future__ import annotations

from homeassistant.exceptions import ServiceValidationError

from ..const import DOMAIN
from ..model.write_rules import Conflict, ReadOnlyPoints, writable
from ..plc import Point


class WriteGuard(ReadOnlyPoints):
    """The read-only points of one PLC, by what they cover, and the check of a write."""

    def check(self, point: Point) -> None:
        """Refuse the write of a (validated) point; raise ServiceValidationError, send nothing."""
        if not writable(self._client, point):
            raise _refused(Conflict("address_not_writable", point))
        if (found := self.conflict(point)) is not None:
            raise _refused(found)


def _refused(conflict: Conflict) -> ServiceValidationError:
    """Return the translated refusal of a write."""
    return ServiceValidationError(
        translation_domain=DOMAIN,
        translation_key=conflict.key,
        translation_placeholders=conflict.placeholders,
    )
