"""Copies of a machine: what a template's stride counts, and the number in a name that counts.

Each vendor moves its own addresses (its address module knows bits, bytes, DB numbers,
datatable elements); the vendors whose points are variable names (TecoApi, PLCnext) find the
part of a name the user says counts (`Shutter_1`, `Shutter[1]`) and move its number here.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
import re
from typing import Final

from .errors import PlcAddressError

BYTES: Final = "bytes"
"""A stride in bytes of the PLC's memory (a bit address moves with its byte)."""
BLOCKS: Final = "blocks"
"""A stride in block numbers (LOGO! I1 + 4 = I5)."""
DATA_BLOCKS: Final = "data_blocks"
"""A stride in data block numbers (S7 DB10 + 1 = DB11: an instance DB per copy)."""
ELEMENTS: Final = "elements"
"""A stride in datatable elements (SoftPLC N7:10 + 5 = N7:15)."""
NAME: Final = "name"
"""A stride of the number in a part of the variable names (Shutter_1 + 1 = Shutter_2)."""

_NUMBERED = re.compile(r"(?P<stem>.*?)(?P<number>[0-9]+)", re.ASCII)

type Segment = str | int


def shifted_name(name: str, by: int) -> str:
    """Return a name with its last number moved (`Shutter_1`, 2 -> `Shutter_3`; zeros kept)."""
    match = _NUMBERED.fullmatch(name)
    if match is None:
        raise PlcAddressError(f"{name} ends in no number to count")
    digits = match["number"]
    number = int(digits) + by
    if number < 0:
        raise PlcAddressError(f"{name}: its number would fall below 0")
    return f"{match['stem']}{number:0{len(digits)}d}"


def shift_segments(
    segments: Sequence[Segment],
    part: Sequence[Segment],
    by: int,
    same: Callable[[str], str],
) -> tuple[Segment, ...]:
    """Return a path's segments with the number of `part`'s last segment moved by `by`.

    `part` is found as consecutive segments of the path, the first place it stands; names
    are compared as `same` spells them (case folded where the PLC ignores case). Its last
    segment counts: an array index, or a name that ends in a number.
    """
    if not part:
        raise PlcAddressError("name the part of the variable names that counts")
    wanted = [same(item) if isinstance(item, str) else item for item in part]
    for start in range(len(segments) - len(part) + 1):
        window = [
            same(item) if isinstance(item, str) else item
            for item in segments[start : start + len(part)]
        ]
        if window == wanted:
            at = start + len(part) - 1
            last = segments[at]
            moved: Segment = last + by if isinstance(last, int) else shifted_name(last, by)
            return (*segments[:at], moved, *segments[at + 1 :])
    raise PlcAddressError("the part that counts is not in this name")
