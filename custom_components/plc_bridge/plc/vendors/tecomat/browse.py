"""TecoApi browsing: the names GetList publishes (3.3), expanded into leaves with a type guess.

TecoApi tells no declared type: GetList lists names only (3.3), GetObject values as JSON (4),
where a BYTE, an INT and a DINT look the same. Every type offered is a guess (`guessed`).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

from ...types import BrowseItem
from .api import TecoApi
from .codec import KINDS, guess_type
from .paths import MISSING, VariablePath, member, plan

FIRST_INDICES = (0, 1)
"""Where an IEC array may start (ARRAY[0..n] or ARRAY[1..n]): the indices tried first."""


@dataclass(slots=True)
class Listing:
    """What a browse found: the leaves, and the variables it could not list (by path)."""

    items: list[BrowseItem] = field(default_factory=list)
    unlisted: list[str] = field(default_factory=list)


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
                listing.items.extend(list(browse_items(path, reading.found[path.key])))
            except RecursionError:  # nested deeper than a stack holds: no PLC program is
                listing.unlisted.append(path.text)
        elif path.key in reading.too_big:
            elements = await array_elements(api, path)
            if elements:
                await expand(api, elements, listing)
            else:
                listing.unlisted.append(path.text)


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


def listed_names(listing: Any) -> list[str]:
    """Return the names of a GetList answer, struct form or array form.

    The spec lists every variable as `"name": {}`. A non-empty object is read as a program
    instance holding its variables (`Main.myObject1`), as GetObject nests them (5.3).
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
            if isinstance(value, dict) and value:
                walk(value, name)
            else:
                names.append(name)

    walk(listing, "")
    return names


def browse_items(path: VariablePath, raw: Any) -> Iterator[BrowseItem]:
    """Yield the leaves of a variable's value: members, elements, or one 5.3 object."""
    if isinstance(raw, dict):
        item = api_object(path, raw)
        if item is not None:
            yield item
            return
        for key, value in raw.items():
            yield from browse_items(VariablePath((*path.segments, str(key))), value)
    elif isinstance(raw, list):
        for index, value in enumerate(raw):
            yield from browse_items(VariablePath((*path.segments, index)), value)
    elif (kind := guess_type(raw)) is not None:
        yield BrowseItem(address=path.text, data_type=kind, guessed=True)


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
