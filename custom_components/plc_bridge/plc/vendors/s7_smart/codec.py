"""S7-200 SMART wire format: nodes packed into requests, values per mode, the status block."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from datetime import datetime, tzinfo
from functools import lru_cache
import json
import reprlib
from typing import Any

from ...codec import (
    check_ascii,
    check_bool,
    check_float,
    check_integer,
    integer_range,
    local_time,
    shortest_real,
)
from ...errors import PlcProtocolError, PlcValueError
from ...planning import pack
from ...types import PlcStatus, Point, Value
from .address import (
    BOOL,
    DATE,
    MAX_STRING,
    MODES,
    Address,
    check_declared,
    parse_address,
    parse_mode,
    point_kind,
)

DATE_FORMAT = "%Y-%m-%d %H:%M:%S"
MAX_NODES = 32  # "max to 32 nodes" (manual 8.1, 9.1)
PAYLOAD_LIMIT = 15 * 1024  # "The overall payload shall not exceed 15KB" (manual 4.3)
NODE_CACHE = 1 << 14
"""Points whose parsed node is kept (about 320 bytes each): above the largest poll planned for
(10,000 points), since a poll past the cap parses every point again at each new plan."""


def check_value(address: Address, kind: str, value: Value, length: int | None = None) -> Value:
    """Return a value coerced for the point; raise PlcValueError when it cannot fit.

    A REAL comes back as the float32 it is stored as (22.3, not 22.299999237060547); a
    string takes at most its declared `length` characters.
    """
    what = address.text
    if kind == BOOL:
        return check_bool(value, what)
    if kind == DATE:
        return _check_date(value)
    if kind == "float":
        return shortest_real(check_float(value, what=what))
    if kind == "string":
        return check_ascii(value, min(length or MAX_STRING, address.room - 1), what)
    if kind == "raw":
        return _check_raw(address, value)
    low, high = integer_range(address.width, signed=kind == "signed")
    return check_integer(value, low, high, what)


def _check_date(value: Value) -> datetime:
    """Return a date and time the PLC's real-time clock can hold."""
    if isinstance(value, str):
        try:
            value = datetime.fromisoformat(value.strip())
        except ValueError as err:
            raise PlcValueError(f"DATE must be a date and time, not {value!r}") from err
    if not isinstance(value, datetime):
        raise PlcValueError(f"DATE must be a date and time, not {value!r}")
    if not 2000 <= value.year <= 2099:
        raise PlcValueError("the PLC clock keeps years 2000..2099 only")
    return value


def _check_raw(address: Address, value: Value) -> list[int]:
    """Return a list of byte values exactly as long as the address is wide."""
    length = address.width // 8
    if (
        not isinstance(value, list)
        or len(value) != length
        or not all(isinstance(b, int) and not isinstance(b, bool) and 0 <= b <= 255 for b in value)
    ):
        raise PlcValueError(f"{address.text} takes a list of {length} byte values (0..255)")
    return value


def encode(kind: str, value: Value, zone: tzinfo) -> Any:
    """Return the JSON value of a checked value; a date goes in the PLC's local time."""
    if kind == BOOL:
        return int(bool(value))
    if isinstance(value, datetime):
        return local_time(value, zone).strftime(DATE_FORMAT)
    return value


def decode(address: Address, kind: str, raw: Any, zone: tzinfo) -> Value:
    """Return the value of a node; raise PlcProtocolError when it does not fit the point."""
    number = isinstance(raw, int | float) and not isinstance(raw, bool)
    try:
        if kind == BOOL and number and raw in (0, 1):
            return bool(raw)
        if kind == DATE and isinstance(raw, str):
            return datetime.strptime(raw, DATE_FORMAT).replace(tzinfo=zone)
        if kind == "string" and isinstance(raw, str):
            return raw
        if kind == "float" and number:
            return shortest_real(float(raw))
        if kind == "raw" and isinstance(raw, list):
            return _check_raw(address, raw)
        if kind in ("signed", "unsigned") and number:
            low, high = integer_range(address.width, signed=kind == "signed")
            return check_integer(raw, low, high)
    except ValueError:
        pass
    raise PlcProtocolError(
        f"{address.text}: the PLC sent {reprlib.repr(raw)}, which is no {kind} value"
    )


def decode_status(status: Any, zone: tzinfo) -> PlcStatus:
    """Return the status block of a read or write reply (Date, Operating Mode, ...)."""
    if not isinstance(status, dict):
        return PlcStatus()
    clock = None
    if isinstance(date := status.get("Date"), str):
        try:
            clock = datetime.strptime(date, DATE_FORMAT).replace(tzinfo=zone)
        except ValueError:
            clock = None
    return PlcStatus(
        mode=_text(status.get("Operating Mode")),
        system=_text(status.get("System Status")),
        force=_text(status.get("Force Status")),
        clock=clock,
    )


def _text(value: Any) -> str | None:
    """Return a status field when it is text."""
    return value if isinstance(value, str) else None


def dumps(value: Any) -> str:
    """Serialize compact JSON, as the manual advises (4.2)."""
    return json.dumps(value, separators=(",", ":"))


# The largest envelope a read or write adds around its nodes (ids stay far below 10**12).
_ENVELOPE = len(dumps({"jsonrpc": "2.0", "method": "write", "id": 10**12, "params": []}))


@dataclass(frozen=True, slots=True)
class Node:
    """One address and mode as it goes on the wire; equal nodes are read once."""

    address: Address
    kind: str
    length: int | None = field(default=None, compare=False)  # a string's declared characters

    def request(self, value: Any = None, *, write: bool = False) -> dict[str, Any]:
        """Return the JSON node; "signed" is the device's default mode and is left out."""
        node: dict[str, Any] = {"var": self.address.text}
        if self.kind in MODES and self.kind != "signed":
            node["mode"] = self.kind
        if write:
            node["value"] = value
        return node


@lru_cache(maxsize=NODE_CACHE)
def node_for(point: Point) -> Node:
    """Parse a point into its wire node (cached: polls ask again); raise PlcAddressError."""
    address = parse_address(point.address)
    mode, length = parse_mode(point.data_type)
    kind = point_kind(address, mode)
    check_declared(address, length)
    return Node(address, kind, length)


def plan[T](
    items: Sequence[T], node_json: Callable[[T], dict[str, Any]], max_nodes: int = MAX_NODES
) -> list[list[T]]:
    """Group items into requests of at most 32 nodes (or fewer) and 15 KB."""
    return pack(
        items,
        lambda item: len(dumps(node_json(item))) + 1,
        PAYLOAD_LIMIT,
        base=_ENVELOPE,
        max_items=max_nodes,
    )


def read_plan(nodes: Sequence[Node], max_nodes: int = MAX_NODES) -> list[list[Node]]:
    """Group the distinct nodes of a poll; a poll without nodes still reads the status."""
    return plan(nodes, Node.request, max_nodes) or [[]]


def reply_nodes(result: dict[str, Any], nodes: Sequence[Node]) -> list[dict[str, Any]]:
    """Return the reply's nodes; refuse a reply that does not match the request node for node."""
    data = result.get("data", [])
    if not isinstance(data, list) or len(data) != len(nodes):
        raise PlcProtocolError(
            f"the PLC answered {len(data) if isinstance(data, list) else 'no'} nodes "
            f"to a request of {len(nodes)}"
        )
    for node, item in zip(nodes, data, strict=True):
        if not isinstance(item, dict) or item.get("var") != node.address.text:
            raise PlcProtocolError(
                f"the PLC's answer does not match the request at {node.address.text}"
            )
    return data
