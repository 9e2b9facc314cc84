"""The PUT of a write: values as the manual's items, and each one checked in the reply.

Words of a file are written as `<data ad="N7:0" count="2">42 0xF73D</data>` (adjacent ones
merged), timer/counter/control and PID words by name (`<data ad="T4:0.PRE">4000</data>`), tags
with count 1. A PUT writes whole words only (the manual has no bit write), so a bit's word is
read first and written back with the bit changed: a bit the PLC program changes in between is
lost, which the manual leaves no way to avoid.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from ...errors import PlcError, PlcProtocolError, PlcWriteRefusedError
from ...types import Point, PointResult, Value
from .address import Address, parse_address
from .codec import (
    data_type,
    encode_float,
    encode_word,
    parse_token,
    printed_unit,
    same_float,
    word_of,
)
from .document import Item
from .planner import ReadItem, item_of, single, span

if TYPE_CHECKING:
    from .client import SoftplcClient

type Cell = tuple[str, int, int, int]  # type, file, element, word


@dataclass(frozen=True, slots=True)
class Sent:
    """A point's value in a PUT item: its position among the item's values and its text."""

    point: Point
    value: Value
    index: int
    token: str


async def write_items(
    client: SoftplcClient, values: Mapping[Point, Value], results: dict[Point, PointResult]
) -> dict[ReadItem, list[Sent]]:
    """Return the PUT items of a write; points that cannot be written get their result now."""
    words: dict[Cell, tuple[str, list[tuple[Point, Value]]]] = {}
    named: dict[ReadItem, list[Sent]] = {}
    bits: list[tuple[Point, Address, Value]] = []
    for point, value in values.items():
        address = parse_address(point.address)
        kind = data_type(address, point.data_type)
        if address.is_tag or address.is_named_word or address.is_opaque or address.word:
            token = _token(kind, value)
            if address.is_tag or address.is_named_word or address.is_opaque:
                item = single(address, token)
            else:  # T4:0.PRE: by its word's name (manual 4.2.1, "Word level")
                keys = frozenset({address.identity})
                item = ReadItem(
                    address.text, None, keys, address.element, values=token, kind="word"
                )
            named.setdefault(item, []).append(Sent(point, value, 0, token))
        elif address.bit is not None:
            bits.append((point, address, value))
        else:
            cell = (address.type, address.file, address.element, 0)
            words[cell] = (_token(kind, value), [(point, value)])
    await _set_bits(client, bits, words, results)
    return _ranges(words) | _merge(named)


def _token(kind: str, value: Value) -> str:
    """Return a checked value as the PUT carries it."""
    if kind == "REAL":
        return encode_float(float(value))  # type: ignore[arg-type]
    if kind == "BOOL":
        return "1" if value else "0"
    return encode_word(word_of(kind, value))


def _merge(named: dict[ReadItem, list[Sent]]) -> dict[ReadItem, list[Sent]]:
    """Return named items, the same word written twice keeping the last value."""
    kept: dict[tuple[str, str], tuple[ReadItem, list[Sent]]] = {}
    for item, sent in named.items():
        kept[item.kind, item.ad] = (item, sent)
    return dict(kept.values())


async def _set_bits(
    client: SoftplcClient,
    bits: list[tuple[Point, Address, Value]],
    words: dict[Cell, tuple[str, list[tuple[Point, Value]]]],
    results: dict[Point, PointResult],
) -> None:
    """Read the words of the bits (one POST), change the bits, and add them to words."""
    if not bits:
        return
    plain = [replace(address, bit=None, bit_name="") for _point, address, _value in bits]
    unwritten = [a for a in plain if (a.type, a.file, a.element, 0) not in words]
    answers, items = await client.fetch(unwritten) if unwritten else ({}, [])
    for (point, address, value), word_address in zip(bits, plain, strict=True):
        cell = (address.type, address.file, address.element, 0)
        try:
            current = words[cell][0] if cell in words else _held(word_address, answers, items)
        except PlcError as err:
            results[point] = PointResult(error=err)
            continue
        word = int(parse_token(current, address.text)) & 0xFFFF
        mask = 1 << (address.bit or 0)
        word = word | mask if value else word & ~mask
        writers = words[cell][1] if cell in words else []
        words[cell] = (encode_word(word), [*writers, (point, value)])


def _held(
    address: Address, answers: Mapping[ReadItem, Item | PlcError], items: list[ReadItem]
) -> str:
    """Return the word the PLC holds at an address (text), or raise the read's error."""
    item = item_of(address, items)
    if item is None:
        raise PlcProtocolError(f"{address.text} was not read")
    answer = answers[item]
    if isinstance(answer, PlcError):
        raise PlcWriteRefusedError(
            f"{address.text}: its word cannot be read to set a bit: {answer}"
        )
    index = (address.element - item.start) * item.words
    if index >= len(answer.tokens):
        raise PlcWriteRefusedError(f"{address.text} lies past the end of its file")
    return answer.tokens[index]


def _ranges(
    words: dict[Cell, tuple[str, list[tuple[Point, Value]]]],
) -> dict[ReadItem, list[Sent]]:
    """Return items writing adjacent words of a file together (count and values agree)."""
    items: dict[ReadItem, list[Sent]] = {}
    run: list[Cell] = []

    def close() -> None:
        if not run:
            return
        type_, file, first, _word = run[0]
        tokens = [words[cell][0] for cell in run]
        item = span(type_, file, first, len(run), 1, values=" ".join(tokens))
        items[item] = [
            Sent(point, value, index, tokens[index])
            for index, cell in enumerate(run)
            for point, value in words[cell][1]
        ]
        run.clear()

    for cell in sorted(words):
        if run and (cell[:2] != run[-1][:2] or cell[2] != run[-1][2] + 1):
            close()
        run.append(cell)
    close()
    return items


def confirm(answer: Item, sent: Sent) -> tuple[PointResult, str]:
    """Return the point's result and, for a write done but not read back, why not.

    The reply must hold the value sent (hex comes back decimal; a REAL as far as its printed
    digits show, READINGS.md row 15). A PUT the PLC answered with the item and no error wrote
    it: an echo that cannot be read, or not told apart from another value, leaves the write
    done but not confirmed; only an echo that reads as another value fails it.
    """
    what = sent.point.address
    done = PointResult(value=sent.value)
    if sent.index >= len(answer.tokens):
        return done, "the PLC's answer lacks the value"
    token = answer.tokens[sent.index]
    try:
        held = parse_token(token, what)
    except PlcError:
        return done, f"the PLC answered {token[:20]!r}"
    wrote = parse_token(sent.token, what)
    if _is_real(sent.point):
        if not same_float(float(wrote), float(held), printed_unit(token)):
            return _other(what, token, sent), ""
        if same_float(float(wrote), float(held)) or printed_unit(token) < 1:
            return done, ""
        return done, f"the PLC answered {token[:20]!r}, without the digits to tell"
    if isinstance(held, float) and not held.is_integer():
        return _other(what, token, sent), ""
    if int(held) & 0xFFFF != int(wrote) & 0xFFFF:
        return _other(what, token, sent), ""
    return done, ""


def _is_real(point: Point) -> bool:
    """True when the point holds a float (its echo is compared as printed)."""
    return data_type(parse_address(point.address), point.data_type) == "REAL"


def _other(what: str, token: str, sent: Sent) -> PointResult:
    """Return the failure of a write the PLC answered with another value."""
    return PointResult(
        error=PlcWriteRefusedError(
            f"{what}: the PLC answered the write with {token[:20]}, not {sent.token}"
        )
    )
