"""PLCnext variable paths: parse, normalize, match in answers, and pack into query strings."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
import functools
import re
from urllib.parse import quote

from ...errors import PlcAddressError
from ...shifting import shift_segments

DEFAULT_PREFIX = "Arp.Plc.Eclr/"
"""The IEC 61131-3 runtime's component: a path without a component lives there."""
MAX_PATH = 512
MAX_URI = 2000  # no documented limit (notes 3a "Limits"): longer lists go in a POST body
EXAMPLES = "MainInstance.Temperature, Arp.Plc.Eclr/Motor.Speed or Main.Recipe[2].Weight"

_NAME = r"[A-Za-z_][A-Za-z0-9_]*"
_COMPONENT = re.compile(rf"{_NAME}(?:\.{_NAME})*", re.ASCII)
_VARIABLE = re.compile(rf"{_NAME}(?:\.{_NAME}|\[\s*\d{{1,9}}\s*\])*", re.ASCII)
_PART = re.compile(rf"\.?({_NAME})|\[\s*(\d+)\s*\]", re.ASCII)

type Segment = str | int


@dataclass(frozen=True, slots=True)
class VariablePath:
    """A parsed path: the component (`Arp.Plc.Eclr`) and the variable's names and indices."""

    component: str
    segments: tuple[Segment, ...]
    text: str = field(init=False, compare=False)  # `Arp.Plc.Eclr/Main.Recipe[2].Weight`
    name: str = field(init=False, compare=False)  # `Main.Recipe[2].Weight`, in its component
    key: str = field(init=False, compare=False)  # as typed: a PLC may tell `a` from `A`

    def __post_init__(self) -> None:
        """Spell the path once."""
        variable = "".join(
            f"[{part}]" if isinstance(part, int) else (f".{part}" if index else part)
            for index, part in enumerate(self.segments)
        )
        object.__setattr__(self, "text", f"{self.component}/{variable}")
        object.__setattr__(self, "name", variable)
        object.__setattr__(self, "key", self.text)

    def child(self, part: Segment) -> VariablePath:
        """Return the path of a member or element of this variable."""
        return VariablePath(self.component, (*self.segments, part))


@functools.lru_cache(maxsize=4096)  # every poll parses the same points again
def parse_path(address: str) -> VariablePath:
    """Parse a variable path; a path without a component is in `Arp.Plc.Eclr/`."""
    text = address.strip()
    component, slash, variable = text.rpartition("/")
    if not slash:
        component = DEFAULT_PREFIX[:-1]
    variable = variable.strip()
    if not _COMPONENT.fullmatch(component.strip()) or not _VARIABLE.fullmatch(variable):
        raise PlcAddressError(
            f"{address!r} is not a PLCnext variable path; write it like {EXAMPLES}"
        )
    segments: list[Segment] = [
        match[1] if match[1] is not None else int(match[2]) for match in _PART.finditer(variable)
    ]
    path = VariablePath(component.strip(), tuple(segments))
    if len(path.text) > MAX_PATH:
        raise PlcAddressError(f"{path.text[:24]}...: a path is at most {MAX_PATH} characters")
    return path


def same_path(answered: object, path: VariablePath) -> bool:
    """True when an answer's `path` names this variable (full, or relative to its component).

    As sent first; else in another case, for a PLC that answers with its own spelling (IEC
    names are case-insensitive; `place` takes such a match only where it is the only one).
    """
    if answered in (path.text, path.name):
        return True
    return isinstance(answered, str) and folded(answered) in (folded(path.text), folded(path.name))


def folded(text: str) -> str:
    """Return a path compared without case (IEC 61131-3 names are case-insensitive)."""
    return text.strip().casefold()


def path_list(paths: Iterable[str]) -> str:
    """Return the `paths` parameter: the paths comma-separated, percent-encoded for a URI."""
    return ",".join(quote(path, safe="/.[]_") for path in paths)


def variables_uri(base: str, paths: Iterable[VariablePath], session: str | None) -> str:
    """Return the GET /variables URI of a read (sessionID keeps the session alive)."""
    query = f"paths={path_list(path.text for path in paths)}"
    if session:
        query = f"sessionID={quote(session, safe='')}&{query}"
    return f"{base}/variables?{query}"


def shift(address: str, part: str, by: int) -> str:
    """Return a path whose counting part moves by `by` (`Shutter[1].` + 1: `Shutter[2].`).

    `part` is the part of the names that counts, as the user wrote it (`HomeInstance.
    Shutter[1].`, `Pump_1`): its last index or its last name's number moves. A part with a
    component must name the point's; names are compared without case (IEC names).
    Raise PlcAddressError.
    """
    path = parse_path(address)
    text = part.strip().rstrip(".").rstrip()
    counting = parse_path(text)
    if "/" in text and folded(counting.component) != folded(path.component):
        raise PlcAddressError(f"{path.text} is not in {counting.component}")
    try:
        segments = shift_segments(path.segments, counting.segments, by, folded)
    except PlcAddressError as err:
        raise PlcAddressError(f"{path.text} ({counting.name}): {err}") from err
    if any(isinstance(item, int) and item < 0 for item in segments):
        raise PlcAddressError(f"{path.text} + {by}: an index would fall below 0")
    return parse_path(VariablePath(path.component, segments).text).text
