"""PLCnext browsing: the eHMI variable dictionary, arrays and structures expanded to leaves.

`/ehmi/data.dictionary.json` lists every HMI variable with its declared type and read-only
flag (notes 3a, Dictionaries); `/ehmi/type.dictionary.json` describes the other types. The
sources give no member list of a structure, so a variable of another type is read once and
its value (JSON objects for structures, lists for arrays) names its leaves.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
import re
from typing import Any

from ...errors import PlcAddressError
from ...types import BrowseItem
from .codec import ALIASES, KINDS
from .paths import VariablePath, parse_path

DATA_DICTIONARY = "/ehmi/data.dictionary.json"
TYPE_DICTIONARY = "/ehmi/type.dictionary.json"
_LOWER = re.compile(r"(-?\d+)\s*\.\.")


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


def lower_bound(about: dict[str, Any] | None) -> int:
    """Return an array type's first index (`Dimensions` like "[1..10]"; 0 when unsaid)."""
    dimensions = about.get("Dimensions") if about else None
    match = _LOWER.search(str(dimensions)) if dimensions is not None else None
    return int(match[1]) if match else 0


def leaves(
    variable: Declared, value: Any, known: dict[str, dict[str, Any]]
) -> Iterator[BrowseItem]:
    """Yield the points of a variable: itself when elementary, else its members and elements."""
    kind = elementary(variable.type)
    if kind is not None:
        yield item(variable.path, kind, variable.read_only)
        return
    about = known.get(variable.type.strip().upper())
    element = elementary(str(about.get("ElementType", ""))) if about else None
    yield from _expand(variable.path, value, element, lower_bound(about), variable.read_only)


def _expand(
    path: VariablePath, value: Any, element: str | None, first: int, read_only: bool
) -> Iterator[BrowseItem]:
    """Yield the leaves of a value; an array's elements take the declared element type."""
    if isinstance(value, dict):
        for key, member in value.items():
            if isinstance(key, str) and key.isidentifier() and key.isascii():
                yield from _expand(path.child(key), member, None, 0, read_only)
    elif isinstance(value, list):
        for index, member in enumerate(value):
            yield from _expand(path.child(first + index), member, element, 0, read_only)
    elif element is not None:
        yield item(path, element, read_only)
    elif (kind := guess(value)) is not None:
        yield item(path, kind, read_only, guessed=True)


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
    return "number" if KINDS[kind] in ("integer", "float") else "sensor"
