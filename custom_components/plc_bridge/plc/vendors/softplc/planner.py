"""The read plan of a poll: one `<data>` item per range of nearby elements of one file.

Pure functions, tested without sockets: `plan` merges, `place` finds each item in a reply by
what the reply's ad names, whether the PLC normalised it (N0007:0033), echoed it (N7:33) or
spelled a tag otherwise; an item the reply does not name unambiguously is left unplaced.
"""

from __future__ import annotations

import bisect
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field

from .address import Address, element_ad, opaque_keys, reply_key
from .document import Item

type Key = tuple[str, int, int, str]
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
    keys: frozenset[Key] = field(default_factory=frozenset)  # places a reply's ad may name
    start: int = 0
    words: int = 1  # words per element
    values: str | None = None  # a PUT's values, space-separated
    kind: str = "range"  # "range", "word" (PD12:3000.SP), "tag" or "opaque" (I1)


def single(address: Address, values: str | None = None) -> ReadItem:
    """Return the item reading (or writing) one address alone, as its ad is sent."""
    if address.is_tag:
        return ReadItem(address.ad, 1, values=values, kind="tag")
    if address.is_opaque:
        return ReadItem(address.ad, 1, opaque_keys(address), values=values, kind="opaque")
    key = frozenset({(address.type, address.file, address.element, address.suffix)})
    return ReadItem(address.ad, None, key, address.element, values=values, kind="word")


def plan(addresses: Iterable[Address], max_gap: int = MAX_GAP_WORDS) -> list[ReadItem]:
    """Return the items reading every address: nearby elements of a file merged into ranges."""
    ranges: dict[tuple[str, int], set[int]] = {}
    singles: dict[tuple[str, str], ReadItem] = {}
    for address in addresses:
        if address.is_tag or address.is_named_word or address.is_opaque:
            item = single(address)
            singles.setdefault((item.kind, item.ad), item)
        else:
            ranges.setdefault(address.range_key, set()).add(address.element)
    items: list[ReadItem] = []
    for (type_, file), elements in sorted(ranges.items()):
        words = Address(type_, file).words
        ordered = sorted(elements)
        first = last = ordered[0]
        for element in ordered[1:]:
            if (element - last - 1) * words > max_gap:
                items.append(span(type_, file, first, last - first + 1, words))
                first = element
            last = element
        items.append(span(type_, file, first, last - first + 1, words))
    return items + list(singles.values())


def span(
    type_: str, file: int, first: int, count: int, words: int, *, values: str | None = None
) -> ReadItem:
    """Return the item reading (or writing) `count` elements of a file from `first`."""
    key = frozenset({(type_, file, first, "")})
    return ReadItem(element_ad(type_, file, first), count, key, first, words, values)


class Locator:
    """Finds the item holding an address among items that do not overlap (a plan's)."""

    def __init__(self, items: Iterable[ReadItem]) -> None:
        """Index the items: single ones by their ad, ranges by file and first element."""
        self._single: dict[str, ReadItem] = {}
        ranges: dict[tuple[str, int], list[ReadItem]] = {}
        for item in items:
            if item.kind != "range":
                self._single.setdefault(item.ad, item)
            else:
                type_, file, _start, _word = next(iter(item.keys))
                ranges.setdefault((type_, file), []).append(item)
        self._ranges = {
            key: (sorted(found, key=_first), sorted(item.start for item in found))
            for key, found in ranges.items()
        }

    def find(self, address: Address) -> ReadItem | None:
        """Return the item holding an address, or None."""
        if address.is_tag or address.is_opaque or address.is_named_word:
            return self._single.get(address.ad)
        found = self._ranges.get(address.range_key)
        if found is None:
            return None
        items, starts = found
        position = bisect.bisect_right(starts, address.element) - 1
        if position < 0:
            return None
        item = items[position]
        return item if address.element < item.start + (item.count or 0) else None


def _first(item: ReadItem) -> int:
    """Return a range's first element (a sort key)."""
    return item.start


def item_of(address: Address, items: Sequence[ReadItem]) -> ReadItem | None:
    """Return the item of a plan that holds an address."""
    return Locator(items).find(address)


def place(
    items: Sequence[ReadItem], reply: Sequence[Item]
) -> tuple[dict[ReadItem, Item], set[ReadItem]]:
    """Return the reply item answering each planned item, and the items told apart from none.

    First by the ad echoed exactly, then by the place it names (normalised or not; a tag in
    another case). Within a group of items and reply items that name each other, an item is
    placed where only one reply item can be its own (one answer per item, counted), or where
    every candidate answer is the same; otherwise the group's items are ambiguous. Last, one
    tag left over takes the one reply item left over (a tag answered with its address).
    """
    keys = [reply_key(answer.ad) for answer in reply]
    texts = [answer.ad.strip() for answer in reply]

    def exact(item: ReadItem, index: int) -> bool:
        return texts[index] == item.ad

    def same_place(item: ReadItem, index: int) -> bool:
        if item.kind == "tag":
            return texts[index].casefold() == item.ad.casefold()
        return keys[index] in item.keys

    placed: dict[ReadItem, Item] = {}
    ambiguous: set[ReadItem] = set()
    free = set(range(len(reply)))
    for matches in (exact, same_place):
        pending = [item for item in items if item not in placed and item not in ambiguous]
        for group, answers in _groups(pending, free, matches):
            found = _match(group, answers, reply, matches)
            if found is None:
                ambiguous.update(group)
                free -= set(answers)
            else:
                placed.update((item, reply[index]) for item, index in found.items())
                free -= set(found.values())
    left = [item for item in items if item not in placed and item not in ambiguous]
    if len(left) == 1 and len(free) == 1 and left[0].kind == "tag":
        placed[left[0]] = reply[free.pop()]
    return placed, ambiguous


def _groups(
    items: list[ReadItem], free: set[int], matches: Callable[[ReadItem, int], bool]
) -> list[tuple[list[ReadItem], list[int]]]:
    """Return the connected groups of items and free reply positions that match each other."""
    links = {item: [index for index in sorted(free) if matches(item, index)] for item in items}
    owner: dict[int, int] = {}  # reply position -> group number
    groups: list[tuple[list[ReadItem], list[int]]] = []
    for item in items:
        if not links[item]:
            continue
        joined = sorted({owner[i] for i in links[item] if i in owner})
        group: tuple[list[ReadItem], list[int]] = ([item], [])
        for number in joined:
            group[0].extend(groups[number][0])
            group[1].extend(groups[number][1])
            groups[number] = ([], [])
        group[1].extend(i for i in links[item] if i not in owner)
        groups.append(group)
        for index in group[1]:
            owner[index] = len(groups) - 1
    return [group for group in groups if group[0]]


def _match(
    items: list[ReadItem],
    answers: list[int],
    reply: Sequence[Item],
    matches: Callable[[ReadItem, int], bool],
) -> dict[ReadItem, int] | None:
    """Return each item's reply position in a group, or None when it cannot be told."""
    found: dict[ReadItem, int] = {}
    if len(items) == len(answers):  # one answer per item: an item with one candidate left takes it
        progress = True
        while progress:
            progress = False
            taken = set(found.values())
            for item in items:
                if item in found:
                    continue
                options = [i for i in answers if i not in taken and matches(item, i)]
                if len(options) == 1:
                    found[item] = options[0]
                    taken.add(options[0])
                    progress = True
    rest = [item for item in items if item not in found]
    spare = [i for i in answers if i not in found.values()]
    if not rest:
        return found
    same = {(reply[i].count, reply[i].tokens, reply[i].error) for i in spare}
    if len(same) != 1 or len(spare) < len(rest):
        return None
    return found | dict(zip(rest, spare, strict=False))
