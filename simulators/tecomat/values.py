"""Typed PLC variables of the Tecomat simulator: IEC types, their JSON forms, checked writes."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import date, datetime
import json
import math
import re
import struct
from typing import Any

INTEGER_RANGES = {
    "BYTE": (0, 0xFF),
    "WORD": (0, 0xFFFF),
    "DWORD": (0, 0xFFFF_FFFF),
    "USINT": (0, 0xFF),
    "UINT": (0, 0xFFFF),
    "UDINT": (0, 0xFFFF_FFFF),
    "SINT": (-0x80, 0x7F),
    "INT": (-0x8000, 0x7FFF),
    "DINT": (-0x8000_0000, 0x7FFF_FFFF),
}
REAL_MAX = 3.4028234663852886e38
TIME_MAX_MS = 2**31 - 1  # 24d 20:31:23.647
DAY_MS = 86_400_000
_CLOCK = re.compile(r"(\d+):([0-5]\d):([0-5]\d)(?:\.(\d{1,3}))?")
_DT = re.compile(r"(\d{4})-(\d\d)-(\d\d)T(\d\d):(\d\d):(\d\d)(?:\.(\d{1,3}))?Z?")


class Fault(Exception):
    """A TecoApi error answer: code "HTTP status.Teco code" and its message (3.7)."""

    def __init__(self, code: str, message: str) -> None:
        super().__init__(code, message)
        self.code = code
        self.message = message

    @property
    def status(self) -> int:
        """The HTTP status of the answer."""
        return int(self.code.split(".")[0])


ERROR_TEXTS = ("manual", "localised", "unnamed")
"""How a PLC words 400.005 and 400.015 (3.7 gives only its English examples). manual: "Variable
'NNN' is not found"; localised: the manual's Czech description ("Proměnná 'NNN' nebyla
nalezena", "Hodnotu VVV nelze zapsat do proměnné 'NNN'"); unnamed: newer wording without the
name ("Variable is not found", "Value was not written")."""

_WORDINGS = {
    "400.005": (
        re.compile(r"Variable '(.*)' is not found", re.DOTALL),
        {"localised": "Proměnná '{1}' nebyla nalezena", "unnamed": "Variable is not found"},
    ),
    "400.015": (
        re.compile(r"Value (.*) was not written to variable '(.*)' \(type of", re.DOTALL),
        {
            "localised": "Hodnotu {1} nelze zapsat do proměnné '{2}'",
            "unnamed": "Value was not written",
        },
    ),
}


def worded(fault: Fault, texts: str) -> str:
    """Return a fault's message as a PLC of the given wording (ERROR_TEXTS) prints it."""
    rule = _WORDINGS.get(fault.code)
    match = rule[0].match(fault.message) if rule else None
    if rule is None or match is None or texts not in rule[1]:
        return fault.message
    return rule[1][texts].format(fault.message, *match.groups())


@dataclass(slots=True)
class Var:
    """One elementary variable: IEC type, value (TIME/TOD in ms, DATE a date, DT naive)."""

    type: str
    value: Any
    length: int = 80  # STRING[n]; Mosaic's default STRING holds 80 characters

    def json(self) -> Any:
        """Return the value as TecoApi sends it (chapter 4)."""
        if self.type in ("REAL", "LREAL"):
            return (Single if self.type == "REAL" else Fixed)(self.value)
        if self.type in ("TIME", "TOD"):
            seconds, millis = divmod(self.value, 1000)
            hours, minutes = seconds // 3600, seconds // 60 % 60
            return f"{hours:02d}:{minutes:02d}:{seconds % 60:02d}.{millis:03d}"
        if self.type == "DATE":
            return self.value.isoformat()
        if self.type == "DT":
            stamp: datetime = self.value
            return f"{stamp:%Y-%m-%dT%H:%M:%S}.{stamp.microsecond // 1000:03d}Z"
        return self.value

    def store(self, raw: Any, name: str) -> Any:
        """Return a JSON value converted for this variable; raise 400.015 when it cannot fit."""
        value = self.convert(raw)
        if value is None:
            raise Fault(
                "400.015",
                f"Value {json.dumps(raw)} was not written to variable '{name}' "
                f"(type of variable is {self.type})",
            )
        return value

    def convert(self, raw: Any) -> Any:
        """Return the stored form of a JSON value, or None when it does not fit."""
        kind = self.type
        number = isinstance(raw, int | float) and not isinstance(raw, bool)
        if kind == "BOOL":
            return bool(raw) if isinstance(raw, bool) or raw in (0, 1) else None
        if kind in INTEGER_RANGES:
            low, high = INTEGER_RANGES[kind]
            return raw if isinstance(raw, int) and number and low <= raw <= high else None
        if kind == "REAL" and number and abs(raw) <= REAL_MAX:
            return struct.unpack("<f", struct.pack("<f", raw))[0]
        if kind == "LREAL" and number:
            return float(raw)
        if not isinstance(raw, str):
            return None
        if kind == "STRING":
            return raw if raw.isascii() and len(raw) <= self.length else None
        return _clock(kind, raw) if kind in ("TIME", "TOD") else _date(kind, raw)


def _clock(kind: str, text: str) -> int | None:
    """Return the milliseconds of a TIME or TOD in range."""
    match = _CLOCK.fullmatch(text)
    if match is None:
        return None
    hours, minutes, seconds, fraction = match.groups()
    millis = ((int(hours) * 60 + int(minutes)) * 60 + int(seconds)) * 1000
    millis += int((fraction or "0").ljust(3, "0"))
    return millis if millis <= (TIME_MAX_MS if kind == "TIME" else DAY_MS - 1) else None


def _date(kind: str, text: str) -> date | datetime | None:
    """Return a DATE or DT from 1970 on."""
    try:
        if kind == "DATE":
            day = date.fromisoformat(text) if len(text) == 10 else None
            return day if day and day.year >= 1970 else None
        match = _DT.fullmatch(text)
        if kind != "DT" or match is None:
            return None
        year, month, day_, hour, minute, second, fraction = match.groups()
        micro = int((fraction or "0").ljust(3, "0")) * 1000
        stamp = datetime(
            int(year), int(month), int(day_), int(hour), int(minute), int(second), micro
        )
    except ValueError:
        return None
    return stamp if stamp.year >= 1970 else None


class Fixed(float):
    """An LREAL (or, as Single, a REAL): printed as REAL_FORMATS says."""


class Single(Fixed):
    """A REAL: a 32-bit float."""


REAL_FORMATS = ("fixed", "shortest")
"""How the PLC prints a REAL or LREAL. fixed: six decimals, as every example of the spec
("varReal": 1000.000000, chapter 4; 0.100000, 5.2); shortest: the shortest text that reads back
as the same float of the type (1e-07), as JSON libraries print."""


def _real(value: Fixed, real_format: str) -> str:
    """Return a REAL or LREAL as the PLC prints it."""
    if real_format == "fixed" or not math.isfinite(value):
        return f"{value:.6f}"
    if isinstance(value, Single):
        packed = struct.pack("<f", value)
        for digits in range(1, 10):
            text = f"{value:.{digits}g}"
            if struct.pack("<f", float(text)) == packed:
                return text
    return repr(float(value))


def dumps(value: Any, real_format: str = "fixed") -> str:
    """Serialize an answer as the PLC does: REALs as `real_format` says, UTF-8 text."""
    if isinstance(value, dict):
        members = (f"{json.dumps(k)}:{dumps(v, real_format)}" for k, v in value.items())
        return "{" + ",".join(members) + "}"
    if isinstance(value, list):
        return "[" + ",".join(dumps(item, real_format) for item in value) + "]"
    if isinstance(value, Fixed):
        return _real(value, real_format)
    return json.dumps(value, ensure_ascii=False)


def leaves(node: Any) -> int:
    """Count the elementary items of a variable (413.004 counts these)."""
    if isinstance(node, dict):
        return sum(leaves(item) for item in node.values())
    if isinstance(node, list):
        return sum(leaves(item) for item in node)
    return 1


class Bounded(list[Any]):
    """An array declared with its first index not 0 (`ARRAY[1..5] OF INT`): its items, first."""

    def __init__(self, low: int, items: list[Any]) -> None:
        super().__init__(items)
        self.low = low


def low_of(node: Any) -> int:
    """Return the first index of an array node (0 unless declared otherwise)."""
    return node.low if isinstance(node, Bounded) else 0


WHOLE_ARRAYS = ("list", "keyed")
"""How a whole array is answered. list: a JSON array of its elements in order, whatever its
first index (5.2 shows only arrays from 0); keyed: an object keyed by each element's declared
index ({"1": 10, "2": 20})."""


def render(node: Any, whole_arrays: str = "list") -> Any:
    """Return the JSON form of a variable: structures as objects, arrays as WHOLE_ARRAYS says."""
    if isinstance(node, dict):
        return {name: render(item, whole_arrays) for name, item in node.items()}
    if isinstance(node, list):
        if whole_arrays == "keyed":
            low = low_of(node)
            return {str(low + at): render(item, whole_arrays) for at, item in enumerate(node)}
        return [render(item, whole_arrays) for item in node]
    return node.json()


def declaration(node: Any) -> str | None:
    """Return a variable's IEC type as a declaration spells it; None for a structure."""
    if isinstance(node, Var):
        return node.type
    if not isinstance(node, list) or not node:
        return None
    ranges = []
    while isinstance(node, list) and node:
        ranges.append(f"{low_of(node)}..{low_of(node) + len(node) - 1}")
        node = node[0]
    inner = declaration(node)
    return f"ARRAY [{', '.join(ranges)}] OF {inner or 'STRUCT'}"
