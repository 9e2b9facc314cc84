"""PLCnext browsing: the eHMI variable dictionary, arrays and structures expanded to leaves.

`/ehmi/data.dictionary.json` lists every HMI variable with its declared type and read-only
flag (notes 3a, Dictionaries); `/ehmi/type.dictionary.json` describes the other types (an
array's element type and bounds). The sources give no member list of a structure, so a
variable of another type is read once and its value (JSON objects for structures, lists for
arrays) names its leaves; a group registered for the members names their types (the Groups
page: a register answer gives each variable's IEC type), then is unregistered.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from ...errors import PlcAddressError
from ...types import BrowseItem
from .codec import ALIASES, KINDS
from .paths import VariablePath, parse_path

DATA_DICTIONARY = "/ehmi/data.dictionary.json"
TYPE_DICTIONARY = "/ehmi/type.dictionary.json"
MAX_DEPTH = 32
"""Levels of structures and arrays followed: a deeper value is no PLC type, and recursion ends."""


@dataclass(frozen=True, slots=True)
class Declared:
    """A variable of the dictionary: its path, type name and read-only flag."""

    path: VariablePath
    type: str
    read_only: bool


def elementary(name: str) -> str | None:
    """Return the client's type name of an elementary IEC type name; None for any other."""
    upper = name.strip().upper()
    upper = ALIASES.get(upper, upper)
    upper = "STRING" if upper.startswith("STRING[") else upper
    upper = "WSTRING" if upper.startswith("WSTRING[") else upper
    return upper if upper in KINDS else None


def declared(dictionary: Any) -> list[Declared]:
    """Return the variables a data dictionary lists (those whose path the client can read)."""
    table = dictionary.get("HmiVariables2") if isinstance(dictionary, dict) else None
    if not isinstance(table, dict):
        return []
    found: list[Declared] = []
    for name, about in table.items():
        if not isinstance(about, dict):
            continue
        try:
            path = parse_path(str(name))
        except PlcAddressError:
            continue
        kind = about.get("Type")
        found.append(Declared(path, str(kind) if kind else "", about.get("ReadOnly") is True))
    return found


def types(dictionary: Any) -> dict[str, dict[str, Any]]:
    """Return the type dictionary's entries by upper-case name."""
    table = dictionary.get("Types") if isinstance(dictionary, dict) else None
    if not isinstance(table, list):
        return {}
    return {
        str(entry["Name"]).upper(): entry
        for entry in table
        if isinstance(entry, dict) and entry.get("Name")
    }


def bounds(about: dict[str, Any] | None) -> tuple[tuple[int, int], ...] | None:
    """Return an array type's (first index, length) per dimension; None when unreadable.

    The Info Center's example: `"Dimensions": [{"StartIndex": 1, "Length": 4}]`.
    """
    dimensions = about.get("Dimensions") if about else None
    if not isinstance(dimensions, list) or not dimensions:
        return None
    found: list[tuple[int, int]] = []
    for dimension in dimensions:
        first = dimension.get("StartIndex") if isinstance(dimension, dict) else None
        length = dimension.get("Length") if isinstance(dimension, dict) else None
        if type(first) is not int or type(length) is not int:  # bool is no bound
            return None
        if length < 0 or abs(first) > 2**31:
            return None
        found.append((first, length))
    return tuple(found)


def members(
    path: VariablePath,
    value: Any,
    type_name: str | None,
    known: dict[str, dict[str, Any]],
    depth: int = 0,
) -> Iterator[VariablePath]:
    """Yield the paths of the structure members in a value (no dictionary gives their types)."""
    if depth > MAX_DEPTH:
        return
    if isinstance(value, list):
        about = known.get(type_name.strip().upper()) if type_name else None
        dims = bounds(about)
        if about is None or dims is None or len(dims) != 1 or dims[0][1] != len(value):
            return
        element = str(about.get("ElementType") or "") or None
        for index, member in enumerate(value):
            yield from members(path.child(dims[0][0] + index), member, element, known, depth + 1)
    elif isinstance(value, dict):
        for key, member in value.items():
            if isinstance(key, str) and key.isidentifier() and key.isascii():
                if not isinstance(member, dict):
                    yield path.child(key)
                yield from members(path.child(key), member, None, known, depth + 1)


def leaves(
    variable: Declared,
    value: Any,
    known: dict[str, dict[str, Any]],
    member_types: dict[str, str] | None = None,
) -> Iterator[BrowseItem]:
    """Yield the points of a variable: itself when elementary, else its members and elements.

    An array's elements are offered only where the type dictionary gives its bounds and the
    value has that many elements, and only for one dimension (no source shows the path of an
    element of a multi-dimensional array); otherwise none are offered.
    """
    if (kind := elementary(variable.type)) is not None:
        yield item(variable.path, kind, variable.read_only)
        return
    for path, member, kind in _walk(variable.path, value, variable.type, known, member_types):
        if kind is not None:
            yield item(path, kind, variable.read_only)
        elif not isinstance(member, dict | list) and (guessed := guess(member)) is not None:
            yield item(path, guessed, variable.read_only, guessed=True)


def _walk(
    path: VariablePath,
    value: Any,
    type_name: str | None,
    known: dict[str, dict[str, Any]],
    member_types: dict[str, str] | None,
    *,
    depth: int = 0,
) -> Iterator[tuple[VariablePath, Any, str | None]]:
    """Yield the leaves of a value with their elementary type (None where undeclared)."""
    if depth > MAX_DEPTH:
        return
    if type_name is not None and (kind := elementary(type_name)) is not None:
        yield path, value, kind
        return
    about = known.get(type_name.strip().upper()) if type_name else None
    if isinstance(value, list):
        dims = bounds(about)
        if about is None or dims is None or len(dims) != 1 or dims[0][1] != len(value):
            return
        element = str(about.get("ElementType") or "") or None
        for index, member in enumerate(value):
            child = path.child(dims[0][0] + index)
            yield from _walk(child, member, element, known, member_types, depth=depth + 1)
    elif isinstance(value, dict):
        for key, member in value.items():
            if isinstance(key, str) and key.isidentifier() and key.isascii():
                child = path.child(key)
                declared_as = (member_types or {}).get(child.key)
                yield from _walk(child, member, declared_as, known, member_types, depth=depth + 1)
    else:
        yield path, value, None


def guess(value: Any) -> str | None:
    """Guess the type of a member the dictionary does not describe (JSON says little)."""
    if isinstance(value, bool):
        return "BOOL"
    if isinstance(value, int):
        return "LINT"
    if isinstance(value, float):
        return "LREAL"
    if isinstance(value, str):
        return "STRING"
    return None


def item(path: VariablePath, kind: str, read_only: bool, *, guessed: bool = False) -> BrowseItem:
    """Return the browse item of one leaf: named by its path in its component, with a platform.

    `guessed`: the dictionary does not declare the leaf's type (a structure's member): it comes
    from the JSON value, and the pick list marks it so.
    """
    return BrowseItem(
        address=path.text,
        name=path.text.partition("/")[2],
        data_type=kind,
        read_only=read_only,
        platform=platform(kind, read_only),
        guessed=guessed,
    )


def platform(kind: str, read_only: bool) -> str:
    """Return the Home Assistant platform a leaf suits."""
    if read_only:
        return "binary_sensor" if kind == "BOOL" else "sensor"
    if kind == "BOOL":
        return "switch"
    if kind in ("DATE", "DT"):
        return "datetime"
    if kind in ("STRING", "WSTRING"):
        return "text"
    return "number" if KINDS[kind] in ("integer", "float", "duration") else "sensor"
