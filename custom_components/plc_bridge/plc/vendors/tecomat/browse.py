"""TecoApi browsing: the names GetList publishes (3.3), expanded into leaves with a type guess.

TecoApi tells no declared type: GetList lists names only (3.3), GetObject values as JSON (4),
where a BYTE, an INT and a DINT look the same. Every type offered is a guess (`guessed`). An
array's elements are offered at their own indices, confirmed by the PLC (READINGS.md row 18).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
import re
from typing import Any

from ...types import BrowseItem
from .api import TecoApi
from .arrays import known
from .codec import KINDS, guess_type
from .paths import MAX_NESTING, MAX_PATH, MISSING, VariablePath, member, plan

FIRST_INDICES = (0, 1)
"""Where an IEC array may start (ARRAY[0..n] or ARRAY[1..n]): the indices tried first."""


@dataclass(slots=True)
class Listing:
    """What a browse found: the leaves, and the variables it could not list (by path)."""

    items: list[BrowseItem] = field(default_factory=list)
    unlisted: list[str] = field(default_factory=list)
    declared: dict[str, tuple[int, ...]] = field(default_factory=dict)  # GetList's first indices
    lows: dict[str, tuple[int, ...]] = field(default_factory=dict)  # confirmed first indices
    lows_by_shape: dict[tuple[object, ...], tuple[int, ...] | None] = field(default_factory=dict)


async def expand(api: TecoApi, paths: list[VariablePath], listing: Listing) -> None:
    """Read the paths and add their leaves to the listing; expand any one too big to answer.

    A variable with more items than one answer holds (413.004) is read element by element when
    it is an array; TecoApi cannot name a structure's members without reading it whole, so such
    a structure is reported as unlisted, never left out in silence.
    """
    reading = await api.get(plan(paths))
    for path in paths:
        if path.key in reading.found:
            try:
                await _leaves(api, path, reading.found[path.key], listing)
            except RecursionError:  # nested deeper than a stack holds: no PLC program is
                listing.unlisted.append(path.text)
        elif path.key in reading.too_big:
            elements = await array_elements(api, path)
            if elements:
                await expand(api, elements, listing)
            else:
                listing.unlisted.append(path.text)
        else:  # unknown, or an answer that cannot place it (READINGS.md rows 1 and 18)
            listing.unlisted.append(path.text)


async def _leaves(api: TecoApi, path: VariablePath, raw: Any, listing: Listing) -> None:
    """Add the leaves of a variable's value: members, elements at their own index, 5.3 objects.

    A JSON array says nothing of its first index: the one GetList declares, else 0, else 1,
    is taken once the PLC confirms its first and last elements; else the array is unlisted.
    """
    if isinstance(raw, dict):
        item = api_object(path, raw)
        if item is not None:
            listing.items.append(item)
            return
        keyed = bool(raw) and all(_INDEX.fullmatch(str(key)) for key in raw)
        for key, value in raw.items():  # keyed by index: the declared ones (READINGS.md 18)
            part: str | int = int(key) if keyed else str(key)
            await _leaves(api, VariablePath((*path.segments, part)), value, listing)
    elif isinstance(raw, list):
        lows = await _first_indices(api, path, _lengths(raw), listing)
        if lows is None:
            listing.unlisted.append(path.text)
            return
        for indices, value in _elements(raw, lows):
            await _leaves(api, VariablePath((*path.segments, *indices)), value, listing)
    elif (kind := guess_type(raw)) is not None:
        listing.items.append(BrowseItem(address=path.text, data_type=kind, guessed=True))


_INDEX = re.compile(r"-?\d{1,9}", re.ASCII)


def _lengths(raw: list[Any]) -> tuple[int, ...]:
    """Return the lengths of a JSON array's dimensions (nested arrays, along the first items)."""
    lengths: list[int] = []
    node: Any = raw
    while isinstance(node, list) and node:
        lengths.append(len(node))
        node = node[0]
    return tuple(lengths)


def _elements(raw: list[Any], lows: tuple[int, ...]) -> Iterator[tuple[tuple[int, ...], Any]]:
    """Yield (indices, value) of an array's elements, numbered from each dimension's first index."""
    if not lows:
        yield (), raw
        return
    for position, item in enumerate(raw):
        if len(lows) > 1 and not isinstance(item, list):
            continue  # ragged: an item that is no array has no elements to offer
        inner = _elements(item, lows[1:]) if len(lows) > 1 else iter([((), item)])
        for indices, value in inner:
            yield (lows[0] + position, *indices), value


async def _first_indices(
    api: TecoApi, path: VariablePath, lengths: tuple[int, ...], listing: Listing
) -> tuple[int, ...] | None:
    """Return each dimension's first index, confirmed by the PLC; None when none is confirmed.

    Arrays of one type inside an array of structures share their answer (one probe each).
    """
    names = tuple(None if isinstance(part, int) else part.lower() for part in path.segments)
    shape = (names, lengths)
    if shape in listing.lows_by_shape:
        return listing.lows_by_shape[shape]
    declared = listing.declared.get(path.key)
    candidates = [declared] if declared and len(declared) == len(lengths) else []
    candidates += [tuple(first for _ in lengths) for first in FIRST_INDICES]
    found = None
    for lows in dict.fromkeys(candidates):
        first = VariablePath((*path.segments, *lows))
        ends = (low + n - 1 for low, n in zip(lows, lengths, strict=True))
        last = VariablePath((*path.segments, *ends))
        if len(last.text) > MAX_PATH or len(lengths) >= MAX_NESTING:
            break  # no name the PLC takes: unlisted
        reading = await api.get([[first, last]] if first != last else [[first]])
        if known(reading, (first, last)):
            found = lows
            break
    listing.lows_by_shape[shape] = found
    if found is not None:
        listing.lows[path.key] = found
    return found


async def array_elements(api: TecoApi, path: VariablePath) -> list[VariablePath]:
    """Return the element paths of an array variable; [] when it is no array.

    The length is found by probing single elements: doubling, then halving, so an array of N
    elements costs about 2·log2(N) small requests (a browse is rare; a poll never does this).
    """

    def element(index: int) -> VariablePath:
        return VariablePath((*path.segments, index))

    for first in FIRST_INDICES:
        if await api.exists(element(first)):
            break
    else:
        return []
    known, step = first, 1  # known: an index that exists
    while await api.exists(element(known + step)):
        known += step
        step *= 2
    low, high = known, known + step  # low exists, high does not
    while high - low > 1:
        middle = (low + high) // 2
        if await api.exists(element(middle)):
            low = middle
        else:
            high = middle
    return [element(index) for index in range(first, low + 1)]


LIST_URI = "/TecoApi/GetList"


def listed_names(listing: Any, declared: dict[str, tuple[int, ...]] | None = None) -> list[str]:
    """Return the names of a GetList answer, struct form or array form.

    The spec lists every variable as `"name": {}`. An object holding a text `type` is read as
    the variable's declaration, and an array's first indices go into `declared` (READINGS.md
    row 18); any other non-empty object as a program instance holding its variables
    (`Main.myObject1`), as GetObject nests them (5.3).
    """
    names: list[str] = []

    def walk(node: Any, prefix: str) -> None:
        if isinstance(node, list):
            for item in node:
                walk(item, prefix)
            return
        if not isinstance(node, dict):
            return
        for key, value in node.items():
            name = f"{prefix}.{key}" if prefix else str(key)
            kind = member(value, "type") if isinstance(value, dict) else MISSING
            if isinstance(kind, str):
                lows = first_indices(kind)
                if lows and declared is not None:
                    declared[name.lower()] = lows
                names.append(name)
            elif isinstance(value, dict) and value:
                walk(value, name)
            else:
                names.append(name)

    walk(listing, "")
    return names


def api_object(path: VariablePath, raw: dict[str, Any]) -> BrowseItem | None:
    """Return the point of a {value, attr{title, units, minValue, maxValue, readOnly}} object.

    The spec's read-only objects leave minValue and maxValue both at 0: no range, then.
    """
    value, attr = member(raw, "value"), member(raw, "attr")
    kind = guess_type(value) if value is not MISSING else None
    if kind is None or not isinstance(attr, dict):
        return None
    low, high = _number(member(attr, "minValue")), _number(member(attr, "maxValue"))
    if low is None or high is None or low >= high:
        low = high = None
    read_only = member(attr, "readOnly") is True
    return BrowseItem(
        address=VariablePath((*path.segments, "value")).text,
        data_type=kind,
        name=_label(member(attr, "title")),
        unit=_label(member(attr, "units")),
        minimum=low,
        maximum=high,
        read_only=read_only,
        platform=suggested_platform(kind, read_only),
        guessed=True,
    )


_RANGES = re.compile(r"\s*ARRAY\s*\[([^\]]*)\]\s*OF\b", re.IGNORECASE | re.ASCII)
_RANGE = re.compile(r"\s*(-?\d{1,9})\s*\.\.\s*(-?\d{1,9})\s*", re.ASCII)


def first_indices(declaration: str) -> tuple[int, ...] | None:
    """Return the first index of each dimension an IEC declaration gives; None for no array.

    `ARRAY [1..2, 1..3] OF INT` and `ARRAY[1..2] OF ARRAY[1..3] OF INT` give (1, 1).
    """
    lows: list[int] = []
    text = declaration
    while (match := _RANGES.match(text)) is not None:
        for part in match[1].split(","):
            bounds = _RANGE.fullmatch(part)
            if bounds is None:
                return None
            lows.append(int(bounds[1]))
        text = text[match.end() :]
    return tuple(lows) or None


def suggested_platform(kind: str, read_only: bool) -> str:
    """Return the Home Assistant platform a published object suits."""
    controls = {"BOOL": "switch", "DATE": "datetime", "DT": "datetime", "STRING": "text"}
    if read_only:
        return "binary_sensor" if kind == "BOOL" else "sensor"
    if kind in controls:
        return controls[kind]
    return "number" if KINDS[kind] in ("integer", "float", "duration") else "sensor"


def _number(value: Any) -> float | None:
    """Return a JSON number as a float (None for anything else)."""
    if isinstance(value, int | float) and not isinstance(value, bool):
        return float(value)
    return None


def _label(value: Any) -> str | None:
    """Return a non-empty text attribute."""
    return value.strip() or None if isinstance(value, str) else None
