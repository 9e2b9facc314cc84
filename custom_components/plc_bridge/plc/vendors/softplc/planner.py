"""The read plan of a poll: one `<data>` item per range of nearby elements of one file.

Pure functions, tested without sockets: `plan` merges, `place` finds each item in a reply
whether the PLC normalised its `ad` (N0007:0033) or echoed it (N7:33), or named a tag.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from .address import Address, element_ad, reply_key
from .document import Item

MAX_GAP_WORDS = 16
"""Words two requested ranges of one file may have between them and still be read as one.

Counted on the simulator's bodies: an item costs 29 bytes in the request
(`<data ad="N7:33" count="10"/>`) and 36 to 44 in the reply (the echoed or normalised ad, the
count, the newlines), about 70 in all, plus one more file lookup in the PLC; a skipped word
costs 2 to 7 bytes ("0 ", "-32768 "). Sixteen words of gap cost less than a second item
unless most skipped words print five digits. With the benchmark's mix (scripts/bench), a
1,000-point poll is one POST of 4 items.
"""


@dataclass(frozen=True, slots=True)
class ReadItem:
    """One `<data>` of a request: a range of elements, a named word or a tag; values to write."""

    ad: str
    count: int | None  # elements; None for a named word (one value)
    key: tuple[str, int, int, str]  # what a reply's ad must name (see reply_key)
    start: int = 0
    words: int = 1  # words per element
    values: str | None = None  # a PUT's values, space-separated


def plan(addresses: Iterable[Address], max_gap: int = MAX_GAP_WORDS) -> list[ReadItem]:
    """Return the items reading every address: nearby elements of a file merged into ranges."""
    ranges: dict[tuple[str, int], list[int]] = {}
    singles: dict[tuple[str, int, int, str], ReadItem] = {}
    for address in addresses:
        if address.is_tag:
            key = ("", 0, 0, address.name.lower())
            singles.setdefault(key, ReadItem(address.name, 1, key))
        elif address.is_named_word:
            key = (address.type, address.file, address.element, address.name)
            singles.setdefault(key, ReadItem(address.text, None, key, address.element))
        else:
            ranges.setdefault(address.range_key, []).append(address.element)
    items: list[ReadItem] = []
    for (type_, file), elements in sorted(ranges.items()):
        words = Address(type_, file).words
        ordered = sorted(set(elements))
        first = last = ordered[0]
        for element in ordered[1:]:
            if (element - last - 1) * words > max_gap:
                items.append(_range(type_, file, first, last, words))
                first = element
            last = element
        items.append(_range(type_, file, first, last, words))
    return items + list(singles.values())


def _range(type_: str, file: int, first: int, last: int, words: int) -> ReadItem:
    """Return the item reading elements first..last of a file."""
    key = (type_, file, first, "")
    return ReadItem(element_ad(type_, file, first), last - first + 1, key, first, words)


def item_of(address: Address, items: Sequence[ReadItem]) -> ReadItem | None:
    """Return the planned item that holds an address."""
    for item in items:
        if address.is_tag:
            if item.key == ("", 0, 0, address.name.lower()):
                return item
        elif address.is_named_word:
            if item.key == (address.type, address.file, address.element, address.name):
                return item
        elif (
            item.key[:2] == address.range_key
            and not item.key[3]
            and item.count is not None
            and item.start <= address.element < item.start + item.count
        ):
            return item
    return None


def place(items: Sequence[ReadItem], reply: Sequence[Item]) -> dict[ReadItem, Item]:
    """Return the reply item answering each planned item; the unanswered ones are missing.

    By what the reply's ad names first; an item left over takes the reply item at its own
    position when the reply has exactly one per request and that one is not claimed (a PLC
    answering a tag with the address it stands for).
    """
    by_key: dict[tuple[str, int, int, str], int] = {}
    for index, answer in enumerate(reply):
        key = reply_key(answer.ad)
        if key is not None:
            by_key.setdefault(key, index)
    placed: dict[ReadItem, Item] = {}
    claimed: set[int] = set()
    for item in items:
        found = by_key.get(item.key)
        if found is not None and found not in claimed:
            placed[item] = reply[found]
            claimed.add(found)
    if len(reply) == len(items):
        for position, item in enumerate(items):
            if item not in placed and position not in claimed:
                known = reply_key(reply[position].ad)
                if known is None or known[0] == "" or item.key[0] == "":
                    placed[item] = reply[position]
                    claimed.add(position)
    return placed
