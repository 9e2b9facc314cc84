"""The PLCnext simulator's HMI variables: IEC types, structures, arrays, checked writes."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from datetime import datetime
import math
import struct
from typing import Any

INTEGERS = {
    "BYTE": (0, 0xFF),
    "WORD": (0, 0xFFFF),
    "DWORD": (0, 0xFFFF_FFFF),
    "LWORD": (0, 2**64 - 1),
    "USINT": (0, 0xFF),
    "UINT": (0, 0xFFFF),
    "UDINT": (0, 0xFFFF_FFFF),
    "ULINT": (0, 2**64 - 1),
    "SINT": (-0x80, 0x7F),
    "INT": (-0x8000, 0x7FFF),
    "DINT": (-(2**31), 2**31 - 1),
    "LINT": (-(2**63), 2**63 - 1),
    "TIME": (-(2**31), 2**31 - 1),
    "LTIME": (-(2**63), 2**63 - 1),
}
PREFIX = "Arp.Plc.Eclr/"


class Refused(Exception):
    """A value the variable cannot take."""


@dataclass(slots=True)
class Leaf:
    """One elementary value."""

    type: str
    value: Any

    def json(self, as_text: bool) -> Any:
        """Return the value as the interface sends it (text where the PLC sends text)."""
        value = self.value
        if self.type == "REAL":
            value = struct.unpack("<f", struct.pack("<f", value))[0]  # 2.412008762359619
        if as_text and not isinstance(value, str):
            return str(value).lower() if isinstance(value, bool) else str(value)
        return value

    def convert(self, raw: Any) -> Any:
        """Return the stored form of a JSON value (a number, or its text); raise Refused."""
        kind = self.type
        if kind == "BOOL":
            if isinstance(raw, bool):
                return raw
            if isinstance(raw, str) and raw.strip().lower() in ("true", "false", "1", "0"):
                return raw.strip().lower() in ("true", "1")
            if raw in (0, 1) and isinstance(raw, int):
                return bool(raw)
        elif kind in INTEGERS:
            number = _number(raw)
            if isinstance(number, float) and number.is_integer():
                number = int(number)
            low, high = INTEGERS[kind]
            if isinstance(number, int) and low <= number <= high:
                return number
        elif kind in ("REAL", "LREAL"):
            number = _number(raw)
            if number is not None and math.isfinite(number):
                if kind == "REAL" and abs(number) > 3.4028234663852886e38:
                    raise Refused
                return float(number)
        elif kind in ("STRING", "WSTRING"):
            one_byte = isinstance(raw, str) and all(ord(char) < 256 for char in raw)
            if isinstance(raw, str) and len(raw) <= 255 and (kind == "WSTRING" or one_byte):
                return raw
        elif kind in ("DT", "DATE") and isinstance(raw, str):
            try:
                datetime.fromisoformat(raw)
            except ValueError:
                raise Refused from None
            return raw
        raise Refused


def _number(raw: Any) -> int | float | None:
    """Return a JSON number, or the number a text holds (pyPLCn writes "500")."""
    if isinstance(raw, bool):
        return None
    if isinstance(raw, int | float):
        return raw
    if isinstance(raw, str):
        try:
            return int(raw.strip())
        except ValueError:
            try:
                return float(raw.strip())
            except ValueError:
                return None
    return None


@dataclass(slots=True)
class Array:
    """An array: its type name, element type, (first index, length) per dimension, elements.

    A multi-dimensional array keeps its elements in nested lists, the first dimension outside.
    """

    type: str
    element: str
    dims: tuple[tuple[int, int], ...]
    items: list[Any]


type Node = Leaf | dict[str, "Node"] | Array


@dataclass(slots=True)
class Variable:
    """An HMI variable: declared type name, value tree, read-only flag."""

    type: str
    node: Node
    read_only: bool = False


def as_json(node: Node | list[Node], as_text: bool) -> Any:
    """Return a value tree as JSON: objects for structures, lists for arrays."""
    if isinstance(node, Leaf):
        return node.json(as_text)
    if isinstance(node, dict):
        return {name: as_json(member, as_text) for name, member in node.items()}
    items = node.items if isinstance(node, Array) else node
    return [as_json(member, as_text) for member in items]


def node_type(node: Node) -> str:
    """Return the type name of a node (a structure member's own type: "" where it has none)."""
    if isinstance(node, Leaf | Array):
        return node.type
    return ""


def arrays(node: Node) -> Iterator[Array]:
    """Yield every array in a value tree (elements of arrays of arrays too)."""
    if isinstance(node, Array):
        yield node
        if not node.items or len(node.dims) != 1:
            return
        node = node.items[0]
        yield from arrays(node)
    elif isinstance(node, dict):
        for member in node.values():
            yield from arrays(member)


@dataclass(slots=True)
class Program:
    """The HMI variables of one project download, by full path.

    `case_sensitive`: names match only as declared (no source says; IEC 61131-3 names are
    case-insensitive, C++ components' are not). Off: any case names the variable.
    """

    variables: dict[str, Variable] = field(default_factory=dict)
    case_sensitive: bool = False
    _names: dict[str, str] = field(default_factory=dict, init=False, repr=False)

    def __post_init__(self) -> None:
        """Index the names case-insensitively (a 1,000-variable group resolves in one pass)."""
        self._names = {name.lower(): name for name in self.variables}

    def rename(self, old: str, new: str) -> None:
        """Rename a variable (a download of a changed project)."""
        self.variables[new] = self.variables.pop(old)
        del self._names[old.lower()]
        self._names[new.lower()] = new

    def _fold(self, text: str) -> str:
        """Return a name as compared."""
        return text if self.case_sensitive else text.lower()

    def declared(self, path: str) -> tuple[str, str] | None:
        """Return the declared name of the variable a path names, and the rest of the path."""
        text = path.strip()
        exact = text if self.case_sensitive else self._names.get(text.lower())
        if exact is not None and exact in self.variables:
            return exact, ""
        folded = self._fold(text)
        for name in self.variables:
            if folded.startswith((self._fold(name) + ".", self._fold(name) + "[")):
                return name, text[len(name) :]
        return None

    def find(self, path: str) -> tuple[Variable, Node] | None:
        """Return the variable and node a full path names (members, `[i]` elements)."""
        found = self.declared(path)
        if found is None:
            return None
        variable = self.variables[found[0]]
        node = _walk(variable, found[1], self.case_sensitive)
        return None if node is None else (variable, node)

    def data_dictionary(self) -> dict[str, Any]:
        """Return `/ehmi/data.dictionary.json`: every HMI variable's type and read-only flag."""
        table = {
            path: {"Type": variable.type, "InitValue": "", "ReadOnly": variable.read_only}
            for path, variable in self.variables.items()
        }
        return {"HmiVariables2": table}

    def type_dictionary(self) -> dict[str, Any]:
        """Return `/ehmi/type.dictionary.json`: the structure and array types.

        Dimensions as in the Info Center's example: `[{"StartIndex": 1, "Length": 4}]`, one
        object per dimension.
        """
        listing: dict[str, dict[str, Any]] = {}
        for variable in self.variables.values():
            if isinstance(variable.node, dict):
                listing.setdefault(
                    variable.type,
                    {
                        "Name": variable.type,
                        "Kind": "Struct",
                        "ElementType": None,
                        "Dimensions": [],
                    },
                )
            for array in arrays(variable.node):
                dims = [{"StartIndex": first, "Length": length} for first, length in array.dims]
                listing.setdefault(
                    array.type,
                    {
                        "Name": array.type,
                        "Kind": "Array",
                        "ElementType": array.element,
                        "Dimensions": dims,
                    },
                )
        return {"Types": list(listing.values())}


def _walk(variable: Variable, rest: str, case_sensitive: bool) -> Node | None:
    """Follow `.member` and `[i]` steps from a variable's node.

    No source shows the path of an element of a multi-dimensional array: none is served.
    """
    node: Node = variable.node
    while rest:
        if rest.startswith("."):
            name, rest = _name(rest[1:])
            if not isinstance(node, dict):
                return None
            match = next(
                (
                    key
                    for key in node
                    if key == name or (not case_sensitive and key.lower() == name.lower())
                ),
                None,
            )
            if match is None:
                return None
            node = node[match]
        elif rest.startswith("["):
            index, _bracket, rest = rest[1:].partition("]")
            if not isinstance(node, Array) or len(node.dims) != 1:
                return None
            if not index.strip().lstrip("-").isdigit():
                return None
            position = int(index) - node.dims[0][0]
            if not 0 <= position < len(node.items):
                return None
            node = node.items[position]
        else:
            return None
    return node


def _name(text: str) -> tuple[str, str]:
    """Split a member name from the steps after it."""
    end = len(text)
    for mark in ".[":
        found = text.find(mark)
        if found != -1:
            end = min(end, found)
    return text[:end], text[end:]
