"""The simulated PLC program (the spec's examples) and the paths TecoApi reads and writes."""

from __future__ import annotations

from datetime import date, datetime
import json
import re
import struct
from typing import Any

from .values import Bounded, Fault, Var, low_of

type Node = Var | dict[str, Node] | list[Node]
type Segment = str | int

MAX_ITEM = 64  # 3.6: an item name of a PutObject body is at most 64 characters
MAX_NESTING = 32  # 3.6: an array item takes two levels
MAX_VALUE = 255  # 3.6: a value is at most 255 characters
_PATH = re.compile(r"[A-Za-z_]\w*(?:\.[A-Za-z_]\w*|\[-?\d+(?:,-?\d+)*\])*", re.ASCII)
_PART = re.compile(r"([A-Za-z_]\w*)|\[([-\d,]+)\]", re.ASCII)
CLOCK = datetime(2018, 1, 31, 16, 50, 39, 949000)
MACHINES = {
    "water": "Boiler.water",
    "target": "Boiler.target",
    "hvac": "Boiler.hvac",
    "mode": "Boiler.mode",
    "alarms": "Boiler.alarms",
    "open": "Shutter.open",
    "close": "Shutter.close",
    "opened": "Shutter.opened",
    "closed": "Shutter.closed",
    "running": "Pump.running",
    "run": "Pump.run",
    "start": "Pump.start",
}
"""The demo machines' public variables by role (simulators/machines.py moves them)."""


def _f32(value: float) -> float:
    """Round to single precision, as a REAL holds it."""
    return float(struct.unpack("<f", struct.pack("<f", value))[0])


def _text(value: str, length: int = 80) -> Var:
    """Return a STRING[length] variable."""
    return Var("STRING", value, length)


def _api_object(value: Var, title: str, read_only: bool, low: float, high: float) -> Node:
    """Return a T_ApiObject of 5.3: the value and its attributes."""
    return {
        "value": value,
        "attr": {
            "enable": Var("BOOL", True),
            "visibility": Var("BOOL", True),
            "readOnly": Var("BOOL", read_only),
            "title": _text(title, 32),
            "minValue": Var("REAL", low),
            "maxValue": Var("REAL", high),
            "units": _text("°C" if value.type == "REAL" else "", 16),
        },
    }


def default_program(bench: int = 1000) -> dict[str, Node]:
    """Return the variables of the spec's example programs (chapters 2 to 5).

    `Main` is the instance of prgMain (5.3); `setTime` is a DT the program copies into its
    clock; `Boiler`, `Shutter` and `Pump` are the demo's machines (`MACHINES`); `BENCH` holds
    `bench` INTs V0, V1, ... for the benchmarks.
    """
    program: dict[str, Node] = {
        "plcName": _text("myFoxtrot", 10),
        "plcType": Var("UINT", 2005),
        "plcDesc": _text("for testing only"),
        "myObject": {
            "first": _text("John", 32),
            "last": _text("Doe", 64),
            "age": Var("USINT", 39),
            "sex": _text("M", 1),
            "salary": Var("UDINT", 70000),
            "married": Var("BOOL", True),
            "registered": Var("BOOL", False),
            "interests": [_text(item, 24) for item in ("Reading", "Mountain Biking", "Hacking")],
            "favorites": {
                "color": _text('"Blue"', 16),
                "sport": _text("Soccer", 24),
                "food": _text("Spaghetti", 32),
            },
        },
        "arr1": [_text(item, 10) for item in ("zero", "one", "two", "three", "four", "")],
        "arr2": [[Var("REAL", _f32(row + col / 10)) for col in range(4)] for row in range(3)],
        "arr3": [
            [[Var("BYTE", 100 * i + 10 * j + k) for k in range(4)] for j in range(3)]
            for i in range(2)
        ],
        "plcData": {
            "varBool0": Var("BOOL", False),
            "varBool1": Var("BOOL", True),
            "varByte": Var("BYTE", 0x11),
            "varWord": Var("WORD", 0x2222),
            "varDword": Var("DWORD", 0x33333333),
            "varUsint": Var("USINT", 11),
            "varUint": Var("UINT", 2222),
            "varUdint": Var("UDINT", 33333333),
            "varSint": Var("SINT", -11),
            "varInt": Var("INT", -2222),
            "varDint": Var("DINT", -33333333),
            "varReal": Var("REAL", 1000.0),
            "varLreal": Var("LREAL", 1000000.0),
            "varTime": Var("TIME", ((120 * 60 + 2) * 60 + 3) * 1000 + 450),
            "varTod": Var("TOD", ((7 * 60 + 30) * 60) * 1000),  # chapter 4's struct lacks a TOD
            "varDate": Var("DATE", date(2015, 6, 17)),
            "varDT": Var("DT", datetime(2014, 5, 11, 11, 22, 33, 456000)),
            "varString": _text("Hello everybody"),
            "varStringArray": [
                _text(item, 8) for item in ("zero", "one", "two", "three", "four", "five")
            ],
        },
        "setTime": Var("DT", CLOCK),
        "Main": {
            "myObject1": _api_object(Var("REAL", -0.5), "outside temperature", True, 0, 0),
            "myObject2": _api_object(Var("REAL", _f32(22.1)), "inside temperature", True, 0, 0),
            "myObject3": _api_object(Var("REAL", 23.0), "requested temperature", False, 10, 30),
            "pump": _api_object(Var("BOOL", False), "circulation pump", False, 0, 0),
        },
    }
    program |= _machines()
    if bench:
        program["BENCH"] = {f"V{index}": Var("INT", index % 1000) for index in range(bench)}
    return program


def bounded_arrays() -> dict[str, Node]:
    """Return arrays whose first index is not 0, which 5.2 forbids (READINGS.md row 18).

    `arrB`: ARRAY[1..5] OF INT (10, 20, ... 50); `arrC`: ARRAY[1..2, 1..3] OF INT (arrC[i, j] =
    10 i + j); `arrN`: ARRAY[-2..2] OF INT (-20, -10, ... 20); `rec.arrS`: ARRAY[1..3] OF INT
    inside a structure (100, 200, 300).
    """
    return {
        "arrB": Bounded(1, [Var("INT", 10 * (index + 1)) for index in range(5)]),
        "arrC": Bounded(
            1, [Bounded(1, [Var("INT", 10 * i + j) for j in (1, 2, 3)]) for i in (1, 2)]
        ),
        "arrN": Bounded(-2, [Var("INT", -20 + 10 * index) for index in range(5)]),
        "rec": {"arrS": Bounded(1, [Var("INT", 100 * index) for index in (1, 2, 3)])},
    }


def _machines() -> dict[str, Node]:
    """Return the demo machines' structures: the boiler's words (INT), the other's bits."""
    machines: dict[str, dict[str, Node]] = {}
    for role, path in MACHINES.items():
        machine, member = path.split(".")
        value = Var("INT", 550 if role == "water" else 0) if machine == "Boiler" else None
        machines.setdefault(machine, {})[member] = value or Var("BOOL", False)
    return dict(machines)


def parse(text: str) -> list[Segment] | None:
    """Return the names and indices of a path (`a.b`, `arr2[1][3]`, `arr2[1,3]`), or None."""
    if not _PATH.fullmatch(text):
        return None
    parts: list[Segment] = []
    for match in _PART.finditer(text):
        if match[1]:
            parts.append(match[1])
        else:
            parts.extend(int(index) for index in match[2].split(","))
    return parts


def spell(parts: list[Segment]) -> str:
    """Return a path as text."""
    text = ""
    for part in parts:
        text += f"[{part}]" if isinstance(part, int) else (f".{part}" if text else part)
    return text


def resolve(variables: dict[str, Node], parts: list[Segment]) -> tuple[list[Segment], Node]:
    """Return the path as the program spells it and its node; names are case-insensitive."""
    node: Any = variables
    canonical: list[Segment] = []
    for part in parts:
        if isinstance(part, int):
            at = part - low_of(node)  # elements are named by their declared index
            if not isinstance(node, list) or not 0 <= at < len(node):
                raise KeyError(part)
            canonical.append(part)
            node = node[at]
            continue
        if not isinstance(node, dict):
            raise KeyError(part)
        key = part if part in node else next((n for n in node if n.lower() == part.lower()), None)
        if key is None:
            raise KeyError(part)
        canonical.append(key)
        node = node[key]
    return canonical, node


def stopped_at(variables: dict[str, Node], parts: list[Segment]) -> str:
    """Return the item where a walk down an unknown path stops: `sport`, `favorites`, `arr1[9]`."""
    end = 1
    while end < len(parts):
        try:
            resolve(variables, parts[:end])
        except KeyError:
            break
        end += 1
    return last_item(parts[:end])


def last_item(parts: list[Segment]) -> str:
    """Return the last item of a path: its last name with the indices that follow it."""
    start = max(index for index, part in enumerate(parts) if isinstance(part, str))
    return spell(parts[start:])


class Pairs(list[tuple[str, Any]]):
    """A JSON object of a PutObject body, its members in order (duplicates kept)."""


def parse_body(body: bytes) -> Pairs:
    """Parse a PutObject body within the PLC parser's limits (3.6); raise 400.009/400.008."""
    if not body.isascii():
        raise Fault("400.009", "JSON syntax error (Unsupported character)")  # our DESC

    def plain(text: str) -> float:
        if "e" in text.lower():
            raise Fault("400.009", "JSON syntax error (Unsupported number format)")  # our DESC
        return float(text)

    try:
        data = json.loads(body, object_pairs_hook=Pairs, parse_float=plain)
    except ValueError as err:
        raise Fault("400.009", f"JSON syntax error ({err.args[0].split(':')[0]})") from None
    if not isinstance(data, Pairs):
        raise Fault("400.009", "JSON syntax error (Expected character '{')")
    if _depth(data) > MAX_NESTING:
        raise Fault("400.009", "JSON syntax error (JSON stack overflow)")
    return data


def _depth(value: Any) -> int:
    """Return the nesting of a parsed body: an object takes one level, an array two."""
    if isinstance(value, Pairs):
        return 1 + max((_depth(item) for _key, item in value), default=0)
    if isinstance(value, list):
        return 2 + max((_depth(item) for item in value), default=0)
    return 0


def assignments(pairs: Pairs, prefix: list[Segment]) -> list[tuple[list[Segment], Any]]:
    """Flatten a body into (path, JSON value); keys may nest, or be dotted (`a.b`, `arr1[5]`)."""
    found: list[tuple[list[Segment], Any]] = []
    for key, value in pairs:
        if len(key) > MAX_ITEM:
            raise Fault("400.008", f"Name of item '{key[:20]}...' is too long")
        parts = parse(key)
        if parts is None:
            raise Fault("400.005", f"Variable '{spell(prefix)}.{key}' is not found")
        found.extend(_flatten(value, prefix + parts))
    return found


def _flatten(value: Any, path: list[Segment]) -> list[tuple[list[Segment], Any]]:
    """Flatten one member: objects and arrays down to their elementary values."""
    if isinstance(value, Pairs):
        return assignments(value, path)
    if isinstance(value, list):
        return [pair for index, item in enumerate(value) for pair in _flatten(item, [*path, index])]
    if isinstance(value, str) and len(value) > MAX_VALUE:
        raise Fault("400.009", "JSON syntax error (Value is too long)")  # our DESC
    return [(path, value)]


def write(
    variables: dict[str, Node],
    pairs: list[tuple[list[Segment], Any]],
    limit: int,
    *,
    leaf_names: bool = False,
) -> list[tuple[Var, Any]]:
    """Check every assignment first; return (variable, stored value) to apply all at once.

    With `leaf_names` an error names only the body's item, as a PLC walking it nested does.
    """
    if len(pairs) > limit:
        raise Fault("413.004", f"Too many variables (maximum is {limit})")
    checked: list[tuple[Var, Any]] = []
    for parts, raw in pairs:
        name = last_item(parts) if leaf_names else spell(parts)
        try:
            _canonical, node = resolve(variables, parts)
        except KeyError:
            shown = stopped_at(variables, parts) if leaf_names else name
            raise Fault("400.005", f"Variable '{shown}' is not found") from None
        if not isinstance(node, Var):
            kind = "STRUCT" if isinstance(node, dict) else "ARRAY"
            raise Fault(
                "400.015",
                f"Value {json.dumps(raw)} was not written to variable '{name}' "
                f"(type of variable is {kind})",
            )
        checked.append((node, node.store(raw, name)))
    return checked


def positions(variables: dict[str, Node], canonical: list[Segment]) -> list[Segment]:
    """Return a resolved path with each index as its position in its array (from 0)."""
    node: Any = variables
    placed: list[Segment] = []
    for part in canonical:
        if isinstance(part, int):
            placed.append(part - low_of(node))
            node = node[part - low_of(node)]
        else:
            placed.append(part)
            node = node[part]
    return placed
