"""TecoApi variable paths: parse, pack into GetObject URIs, find in answers, nest for PutObject."""

from __future__ import annotations

from collections import deque
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
import functools
import re
from typing import Any

from ...errors import PlcAddressError, PlcValueError
from ...shifting import shift_segments

SERVICE = "/TecoApi/"
GET_OBJECT = SERVICE + "GetObject?"
MAX_URI = 256  # "Celková délka dotazu může být max. 256 znaků" (3.4, 3.5)
ROOM = MAX_URI - len(GET_OBJECT) + 1  # the names of a GetObject URI, each paying one "&"
MAX_VARIABLES = 128  # 413.002/413.004: Foxtrot CP-1xxx 128, CP-2xxx 256; the smaller is safe
MAX_PATH = 128  # 400.007: a variable name of CP-1xxx is at most 128 characters
MAX_NAME = 64  # chapter 4: an IEC name is at most 64 characters; 400.008: an item name too
MAX_NESTING = 32  # 3.6: the PutObject parser nests at most 32 levels
EXAMPLES = "plcType, myObject.favorites.sport, arr2[1][3] or Main.myObject3.value"

_NAME = r"[A-Za-z_][A-Za-z0-9_]*"
_PATH = re.compile(rf"{_NAME}(?:\s*\.\s*{_NAME}|\s*\[[\s\d,-]*\])*", re.ASCII)
_PART = re.compile(rf"\.\s*({_NAME})|\[([\s\d,-]*)\]|({_NAME})", re.ASCII)

type Segment = str | int


@dataclass(frozen=True, slots=True)
class VariablePath:
    """A parsed variable path: names and array indices, as the PLC program spells them."""

    segments: tuple[Segment, ...]
    text: str = field(init=False, compare=False)  # `myObject.favorites.sport`, `arr2[1][3]`
    key: str = field(init=False, compare=False)  # compared as the PLC does: case-insensitively
    first_index: int = field(init=False, compare=False)  # where the first index is; 0: none

    def __post_init__(self) -> None:
        """Spell the path once: polls use it for every request and answer."""
        text = "".join(
            f"[{part}]" if isinstance(part, int) else (f".{part}" if index else part)
            for index, part in enumerate(self.segments)
        )
        object.__setattr__(self, "text", text)
        object.__setattr__(self, "key", text.lower())
        first = next((at for at, part in enumerate(self.segments) if isinstance(part, int)), 0)
        object.__setattr__(self, "first_index", first)

    def write_keys(self) -> list[str]:
        """The object keys of a PutObject body: a name with the indices that follow it.

        The spec's bodies nest whole structures and arrays only (chapter 5); an array element
        is sent as "arr1[5]", the spelling GetObject and SetObject take (5.2).
        """
        keys: list[str] = []
        for part in self.segments:
            if isinstance(part, int):
                keys[-1] += f"[{part}]"
            else:
                keys.append(part)
        return keys


@functools.lru_cache(maxsize=4096)  # every poll parses the same points again
def parse_path(address: str) -> VariablePath:
    """Parse a variable path; raise PlcAddressError with a message for the point form."""
    text = address.strip()
    if not _PATH.fullmatch(text):
        raise PlcAddressError(
            f"{address!r} is not a TecoApi variable path; write it like {EXAMPLES}"
        )
    segments: list[Segment] = []
    for match in _PART.finditer(text):
        name = match[1] or match[3]
        if name is not None:
            _check_name(name)
            segments.append(name)
            continue
        indices = [item.strip() for item in match[2].split(",")]
        # ASCII, and at most 9 digits: int() refuses over 4,300, and no PLC array is that long.
        # IEC 61131-3 arrays may start below 0 (ARRAY[-2..2]): a sign is taken.
        if not all(_index(item) for item in indices):
            raise PlcAddressError(f"{text}: an array index is a whole number, as in arr2[1][3]")
        segments.extend(int(item) for item in indices)  # arr2[1, 3] is arr2[1][3]
    path = VariablePath(tuple(segments))
    if len(path.text) > MAX_PATH:
        raise PlcAddressError(f"{path.text[:24]}...: a path is at most {MAX_PATH} characters")
    return path


def _index(item: str) -> bool:
    """True for an array index as a path spells it: ASCII digits, perhaps after a minus."""
    digits = item.removeprefix("-")
    return digits.isascii() and digits.isdigit() and len(digits) <= 9


def _check_name(name: str) -> None:
    """Refuse names IEC 61131-3 does not allow (chapter 4, "Jména proměnných")."""
    if len(name) > MAX_NAME:
        raise PlcAddressError(f"{name[:24]}...: a name is at most {MAX_NAME} characters")
    if "__" in name:
        raise PlcAddressError(f"{name}: IEC names never hold two underscores in a row")


def check_writable(path: VariablePath) -> None:
    """Refuse a path the PutObject parser cannot take (3.6: item names, nesting)."""
    keys = path.write_keys()
    for key in keys:
        if len(key) > MAX_NAME:
            raise PlcValueError(
                f"{path.text}: the PLC takes item names of at most {MAX_NAME} characters ({key})"
            )
    if len(keys) >= MAX_NESTING:
        raise PlcValueError(f"{path.text}: the PLC nests at most {MAX_NESTING} levels")


def pack_names(names: Sequence[str]) -> list[list[str]]:
    """Group names into the fewest GetObject URIs of at most 256 characters.

    Minimum bin slack: each URI takes the longest name left, then the names that fill its
    room most closely (a subset sum over name lengths, longer names preferred); first fit
    decreasing instead in the rare plans where that needs fewer. A name costs its length plus
    an "&"; a URI holds at most 119 names, so the 128-name limit cannot bind.
    """
    ordered = sorted(names, key=len, reverse=True)
    closest, first = _closest_fit(ordered), _first_fit(ordered)
    return first if len(first) < len(closest) else closest


def _first_fit(ordered: list[str]) -> list[list[str]]:
    """Pack names, longest first, each into the first URI with room for it."""
    groups: list[list[str]] = []
    free: list[int] = []
    for name in ordered:
        cost = len(name) + 1
        for index, left in enumerate(free):
            if left >= cost:
                groups[index].append(name)
                free[index] -= cost
                break
        else:
            groups.append([name])
            free.append(ROOM - cost)
    return groups


def _closest_fit(ordered: list[str]) -> list[list[str]]:
    """Pack names, longest first, filling each URI as closely as the names left allow."""
    by_cost: dict[int, deque[str]] = {}
    for name in ordered:
        by_cost.setdefault(len(name) + 1, deque()).append(name)
    groups: list[list[str]] = []
    while by_cost:
        largest = max(by_cost)
        taken = {largest: 1}
        fill = _fill({cost: len(left) for cost, left in by_cost.items()}, taken, ROOM - largest)
        group: list[str] = []
        for cost in sorted(fill, reverse=True):
            left = by_cost[cost]
            group.extend(left.popleft() for _ in range(fill[cost]))
            if not left:
                del by_cost[cost]
        groups.append(group)
    return groups


def _fill(counts: dict[int, int], taken: dict[int, int], space: int) -> dict[int, int]:
    """Add to taken the costs (name counts by cost) whose sum comes closest to space.

    Counts are split into powers of two, so reachable sums are one integer bit set per step.
    """
    pieces: list[tuple[int, int]] = []
    for cost in sorted(counts, reverse=True):
        left = min(counts[cost] - taken.get(cost, 0), max(space, 0) // cost)
        step = 1
        while left > 0:
            pieces.append((cost, min(step, left)))
            left -= step
            step *= 2
    mask = (1 << max(space, 0) + 1) - 1
    reach = [1]
    for cost, count in pieces:
        reach.append((reach[-1] | reach[-1] << cost * count) & mask)
    total = reach[-1].bit_length() - 1
    for index in range(len(pieces), 0, -1):  # undo the last pieces first: longer names win
        if not reach[index - 1] >> total & 1:
            cost, count = pieces[index - 1]
            taken[cost] = taken.get(cost, 0) + count
            total -= cost * count
    return taken


def plan(paths: Iterable[VariablePath]) -> list[list[VariablePath]]:
    """Group distinct paths into GetObject requests (see `pack_names`).

    Each request names the elements of one array in index order, so an answer that lists only
    the asked elements lists them in that order too.
    """
    by_text = {path.text: path for path in paths}
    groups = [[by_text[text] for text in group] for group in pack_names(list(by_text))]
    return [
        sorted(group, key=_order) if any("[" in path.text for path in group) else group
        for group in groups
    ]


def _order(path: VariablePath) -> tuple[tuple[int, int, str], ...]:
    """Sort key of a path: names case-insensitively, indices as numbers."""
    return tuple(
        (1, part, "") if isinstance(part, int) else (0, 0, part.lower()) for part in path.segments
    )


def get_uri(names: Iterable[str]) -> str:
    """Return the GetObject request target for names (sent verbatim, as the spec shows it)."""
    return GET_OBJECT + "&".join(names)


MISSING = object()


def member(node: dict[str, Any], name: str) -> Any:
    """Return a member of an answer object; names are case-insensitive (3.4)."""
    if name in node:
        return node[name]
    wanted = name.lower()
    for key, value in node.items():
        if key.lower() == wanted:
            return value
    return MISSING


def nest(items: Iterable[tuple[VariablePath, Any]]) -> dict[str, Any]:
    """Return the PutObject body for (path, JSON value) pairs: shared parents merged once."""
    body: dict[str, Any] = {}
    spelled: dict[int, dict[str, str]] = {}  # id(object) -> lower-case key -> key as first sent
    for path, value in items:
        node = body
        keys = path.write_keys()
        for depth, spelling in enumerate(keys):
            names = spelled.setdefault(id(node), {})
            key = names.setdefault(spelling.lower(), spelling)
            if depth == len(keys) - 1:
                if isinstance(node.get(key), dict):
                    raise PlcValueError(f"{path.text} holds other variables written here")
                node[key] = value
                break
            child = node.setdefault(key, {})
            if not isinstance(child, dict):
                raise PlcValueError(f"{path.text} lies inside a variable written as a value")
            node = child
    return body


def shift(address: str, part: str, by: int) -> str:
    """Return a path whose counting part moves by `by` (`Shutter_1.` + 1: Shutter_2.Position).

    `part` is the part of the names that counts, as the user wrote it (`Shutter_1.`,
    `Main.Shutter_1`, `arr[1]`): its last name's number or its last index moves. Names are
    compared case-insensitively, as the PLC does. Raise PlcAddressError.
    """
    path = parse_path(address)
    counting = parse_path(part.strip().rstrip(".").rstrip())
    try:
        segments = shift_segments(path.segments, counting.segments, by, str.casefold)
    except PlcAddressError as err:
        raise PlcAddressError(f"{path.text} ({counting.text}): {err}") from err
    return parse_path(VariablePath(segments).text).text
