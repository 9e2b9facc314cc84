"""S7-200 SMART wire format: result codes, nodes packed into requests, values per mode."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from datetime import datetime, tzinfo
from functools import lru_cache
import json
from typing import Any

from ...codec import (
    check_ascii,
    check_bool,
    check_float,
    check_integer,
    integer_range,
    local_time,
)
from ...errors import (
    PlcAddressError,
    PlcError,
    PlcProtocolError,
    PlcValueError,
    PlcWriteRefusedError,
)
from ...planning import pack
from ...types import PlcStatus, Point, Value
from .address import BOOL, DATE, MODES, Address, parse_address, point_kind

# The manual's error page is missing: only 3004 "Invalid address." is the vendor's own (it appears
# in the read and write examples). Every other code here is a guess that only refines a message:
# what happened is decided from the structure the manual defines (client.S7SmartClient._call).
# The simulator answers with these or, with foreign_codes, with others; tests run both.
PARSE_ERROR = -32700
INVALID_REQUEST = -32600
METHOD_NOT_FOUND = -32601
INVALID_PARAMS = -32602
LOGIN_FAILED = 1001
INVALID_TOKEN = 1002  # missing, replaced by a newer login of the same user, logged out or idle
PERMISSION_DENIED = 1003
NOT_IN_RUN = 2001
TOO_MANY_NODES = 2002
PAYLOAD_TOO_LARGE = 2003
INVALID_ADDRESS = 3004
INVALID_MODE = 3005
INVALID_VALUE = 3006  # out of range, or the wrong JSON type for the mode
READ_ONLY = 3007
ERRORS: dict[int, str] = {
    PARSE_ERROR: "Parse error.",
    INVALID_REQUEST: "Invalid Request.",
    METHOD_NOT_FOUND: "Method not found.",
    INVALID_PARAMS: "Invalid params.",
    LOGIN_FAILED: "Login failed.",
    INVALID_TOKEN: "Invalid token.",
    PERMISSION_DENIED: "Permission denied.",
    NOT_IN_RUN: "CPU not in RUN.",
    TOO_MANY_NODES: "Too many nodes.",
    PAYLOAD_TOO_LARGE: "Payload too large.",
    INVALID_ADDRESS: "Invalid address.",
    INVALID_MODE: "Invalid mode.",
    INVALID_VALUE: "Invalid value.",
    READ_ONLY: "Read-only address.",
}

STOP_MESSAGE = "the PLC is in STOP; S7-200 SMART accepts writes only in RUN"
DATE_FORMAT = "%Y-%m-%d %H:%M:%S"
MAX_NODES = 32  # "max to 32 nodes" (manual 8.1, 9.1)
PAYLOAD_LIMIT = 15 * 1024  # "The overall payload shall not exceed 15KB" (manual 4.3)
MAX_STRING = 254  # an S7-200 SMART string: one length byte, then up to 254 ASCII characters
_NODE_ERRORS: dict[int, tuple[type[PlcError], str]] = {
    INVALID_ADDRESS: (PlcAddressError, "the PLC has no such address"),
    INVALID_MODE: (PlcAddressError, "the PLC refused this data type for the address"),
    INVALID_VALUE: (PlcAddressError, "the PLC refused the value (out of range or wrong type)"),
    READ_ONLY: (PlcWriteRefusedError, "the address is read-only"),
}


class RequestRefused(PlcProtocolError):
    """The PLC answered a whole request with an error object that no fresh login cured."""


def request_error(code: int, message: str) -> PlcError:
    """Return the exception for a refused request that a fresh login did not cure.

    Never an authentication error: the login just worked. A code this table knows refines the
    kind; any other keeps the PLC's own words.
    """
    text = message or ERRORS.get(code, "no message")
    if code == PERMISSION_DENIED:
        return PlcWriteRefusedError(f"the PLC user has no write permission ({text})")
    if code == NOT_IN_RUN:
        return PlcWriteRefusedError(STOP_MESSAGE)
    return RequestRefused(f"the PLC refused the request: {text} (code {code})")


def node_error(code: Any, var: str, message: Any = None, *, write: bool = False) -> PlcError:
    """Return the exception for a node whose result code is not 0, with the PLC's own words.

    A code this table knows refines the kind; any other is, by structure, the PLC refusing that
    node: a write it did not take, or a read it could not answer (manual 8.3.1, 9.3.1: "If
    errors exist, nodes shall return the exact reason").
    """
    words = f": {message}" if isinstance(message, str) and message.strip() else ""
    if code in _NODE_ERRORS:
        kind, text = _NODE_ERRORS[code]
        said = "" if message == ERRORS.get(code) else words  # no echo of what the table says
        return kind(f"{var}: {text}{said} (code {code})")
    kind = PlcWriteRefusedError if write else PlcProtocolError
    return kind(f"{var}: the PLC refused it{words or ' without a reason'} (code {code!r})")


def check_value(address: Address, kind: str, value: Value) -> Value:
    """Return a value coerced for the point; raise PlcValueError when it cannot fit."""
    what = address.text
    if kind == BOOL:
        return check_bool(value, what)
    if kind == DATE:
        return _check_date(value)
    if kind == "float":
        return check_float(value, what=what)
    if kind == "string":
        return check_ascii(value, min(MAX_STRING, address.room - 1), what)
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
            return float(raw)
        if kind == "raw" and isinstance(raw, list):
            return _check_raw(address, raw)
        if kind in ("signed", "unsigned") and number:
            low, high = integer_range(address.width, signed=kind == "signed")
            return check_integer(raw, low, high)
    except ValueError:
        pass
    raise PlcProtocolError(f"{address.text}: the PLC sent {raw!r}, which is no {kind} value")


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

    def request(self, value: Any = None, *, write: bool = False) -> dict[str, Any]:
        """Return the JSON node; "signed" is the device's default mode and is left out."""
        node: dict[str, Any] = {"var": self.address.text}
        if self.kind in MODES and self.kind != "signed":
            node["mode"] = self.kind
        if write:
            node["value"] = value
        return node


@lru_cache(maxsize=4096)
def node_for(point: Point) -> Node:
    """Parse a point into its wire node (cached: polls ask again); raise PlcAddressError."""
    address = parse_address(point.address)
    return Node(address, point_kind(address, point.data_type))


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
