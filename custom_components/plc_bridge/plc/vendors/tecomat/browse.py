"""TecoApi browsing: the names GetList publishes (3.3), expanded into leaves with a type guess."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from ...types import BrowseItem
from .codec import KINDS, guess_type
from .paths import MISSING, VariablePath, member

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
        yield BrowseItem(address=path.text, data_type=kind)


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
    )


def suggested_platform(kind: str, read_only: bool) -> str:
    """Return the Home Assistant platform a published object suits."""
    controls = {"BOOL": "switch", "DATE": "datetime", "DT": "datetime", "STRING": "text"}
    if read_only:
        return "binary_sensor" if kind == "BOOL" else "sensor"
    if kind in controls:
        return controls[kind]
    return "number" if KINDS[kind] in ("integer", "float") else "sensor"


def _number(value: Any) -> float | None:
    """Return a JSON number as a float (None for anything else)."""
    if isinstance(value, int | float) and not isinstance(value, bool):
        return float(value)
    return None


def _label(value: Any) -> str | None:
    """Return a non-empty text attribute."""
    return value.strip() or None if isinstance(value, str) else None
