"""A point's value in a poll: its address parsed once, its value taken from its item's answer."""

from __future__ import annotations

from dataclasses import dataclass

from ...errors import PlcAddressError, PlcError, PlcProtocolError
from ...types import Point, PointResult
from .address import Address, parse_address
from .codec import data_type, decode, parse_token
from .document import Item
from .exchange import Refused
from .planner import Key, ReadItem


@dataclass(frozen=True, slots=True)
class Wanted:
    """A valid point of a read: its address, type, identity and text, parsed once."""

    point: Point
    address: Address
    kind: str
    key: Key
    text: str


def wanted_of(point: Point) -> Wanted | PlcError:
    """Return what a read needs of a point, or why it cannot be read."""
    try:
        address = parse_address(point.address)
        kind = data_type(address, point.data_type)
    except PlcError as err:
        return err
    return Wanted(point, address, kind, address.identity, address.text)


def result_of(want: Wanted, item: ReadItem, answer: Item | PlcError) -> PointResult:
    """Return a point's value out of its item's reply."""
    if isinstance(answer, PlcError):
        if isinstance(answer, Refused):
            return PointResult(error=PlcAddressError(f"{want.text}: {answer}"))
        return PointResult(error=answer)
    what = want.text
    tokens = answer.tokens
    counted = item.count is not None and answer.count is not None and not want.address.is_tag
    if counted and len(tokens) != (answer.count or 0) * item.words:
        return PointResult(
            error=PlcProtocolError(
                f"{what}: the PLC answered {len(tokens)} values for {answer.count} elements "
                f"of {item.words} words"
            )
        )
    index = 0
    if item.kind == "range":
        index = (want.address.element - item.start) * item.words + want.address.word
    if index >= len(tokens):
        return PointResult(
            error=PlcAddressError(
                f"{what} lies past the end of its file (the PLC answered "
                f"{len(tokens) // item.words} elements from {item.ad})"
            )
        )
    try:
        raw = parse_token(tokens[index], what)
        return PointResult(value=decode(want.kind, raw, want.address.bit, what))
    except PlcError as err:
        return PointResult(error=err)
