"""TecoApi variable paths: parse, pack into GetObject URIs, find in answers, nest for PutObject."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
import functools
import re
from typing import Any

from ...errors import PlcAddressError, PlcValueError

SERVICE = "/TecoApi/"
GET_OBJECT = SERVICE + "GetObject?"
MAX_URI = 256  # "Celková délka dotazu může být max. 256 znaků" (3.4, 3.5)
MAX_VARIABLES = 128  # 413.002/413.004: Foxtrot CP-1xxx 128, CP-2xxx 256; the smaller is safe
MAX_PATH = 128  # 400.007: a variable name of CP-1xxx is at most 128 characters
MAX_NAME = 64  # chapter 4: an IEC name is at most 64 characters; 400.008: an item name too
MAX_NESTING = 32  # 3.6: the PutObject parser nests at most 32 levels
EXAMPLES = "plcType, myObject.favorites.sport, arr2[1][3] or Main.myObject3.value"

_NAME = r"[A-Za-z_][A-Za-z0-9_]*"
_PATH = re.compile(rf"{_NAME}(?:\s*\.\s*{_NAME}|\s*\[[\s\d,]*\])*", re.ASCII)
_PART = re.compile(rf"\.\s*({_NAME})|\[([\s\d,]*)\]|({_NAME})", re.ASCII)

type Segment = str | int


@dataclass(frozen=True, slots=True)
class VariablePath:
    """A parsed variable path: names and array indices, as the PLC program spells them."""

    segments: tuple[Segment, ...]
    text: str = field(init=False, compare=False)  # `myObject.favorites.sport`, `arr2[1][3]`
    key: str = field(init=False, compare=False)  # compared as the PLC does: case-insensitively

    def __post_init__(self) -> None:
        """Spell the path once: polls use it for every request and answer."""
        text = "".join(
            f"[{part}]" if isinstance(part, int) else (f".{part}" if index else part)
            for index, part in enumerate(self.segments)
        )
        object.__setattr__(self, "text", text)
        object.__setattr__(self, "key", text.lower())

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
        if not all(item.isdigit() for item in indices):
            raise PlcAddressError(f"{text}: an array index is a whole number, as in arr2[1][3]")
        segments.extend(int(item) for item in indices)  # arr2[1, 3] is arr2[1][3]
    path = VariablePath(tuple(segments))
    if len(path.text) > MAX_PATH:
        raise PlcAddressError(f"{path.text[:24]}...: a path is at most {MAX_PATH} characters")
    return path


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
    """Group names into the fewest GetObject URIs of at most 256 characters and 128 names.

    First fit, longest names first: the URI limit is the only cost, so this nearly always
    reaches the bound of total length divided by room.
    """
    room = MAX_URI - len(GET_OBJECT) + 1  # every name but the first pays one "&"
    groups: list[list[str]] = []
    left: list[int] = []
    for name in sorted(names, key=len, reverse=True):
        cost = len(name) + 1
        for index, free in enumerate(left):
            if free >= cost and len(groups[index]) < MAX_VARIABLES:
                groups[index].append(name)
                left[index] -= cost
                break
        else:
            groups.append([name])
            left.append(room - cost)
    return groups


def plan(paths: Iterable[VariablePath]) -> list[list[VariablePath]]:
    """Group distinct paths into GetObject requests (see `pack_names`)."""
    by_text = {path.text: path for path in paths}
    return [[by_text[text] for text in group] for group in pack_names(list(by_text))]


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


def find(answer: Any, path: VariablePath) -> Any:
    """Return the value at path in a nested GetObject answer; raise KeyError when absent.

    Members nest as in chapter 5.1. The spec shows no answer for an array element: whole arrays
    are JSON arrays (5.2), and an element may also come keyed "arr1[2]" in its parent object.
    """
    return _walk(answer, path.segments, 0)


def _walk(node: Any, segments: tuple[Segment, ...], at: int) -> Any:
    """Follow segments[at:] down from node."""
    if at == len(segments):
        return node
    part = segments[at]
    if isinstance(part, int):
        if isinstance(node, list) and part < len(node):
            return _walk(node[part], segments, at + 1)
        raise KeyError(part)
    if not isinstance(node, dict):
        raise KeyError(part)
    end = at + 1
    while end < len(segments) and isinstance(segments[end], int):
        end += 1
    for stop in range(end, at, -1):  # "arr2[1][3]", then "arr2[1]", then "arr2"
        key = part + "".join(f"[{index}]" for index in segments[at + 1 : stop])
        value = member(node, key)
        if value is not MISSING:
            try:
                return _walk(value, segments, stop)
            except KeyError:
                continue
    raise KeyError(part)


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
