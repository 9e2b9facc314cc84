"""S7comm multi-variable read and write PDUs, per-item return codes, and what SZL lists say.

python-snap7 3.3.0 builds the session PDUs (setup, SZL, clock), parses every reply, and encodes
each address spec here (`S7DataTypes.encode_address`). Its multi-variable layer does not fit, as
its source shows:

- `S7Protocol.build_multi_read_request` forces word length BYTE and casts the area to its
  `S7Area` enum, which has no P area (0x80) nor the S7-200 timer/counter codes (0x1E/0x1F):
  those raise ValueError, and T/C items need their own word length. There is no multi-write
  builder at all, so no BIT items.
- `S7Protocol.extract_multi_read_data` raises on the first item whose code is not 0xFF: one
  missing DB would hide every other value of the request.
- `AsyncClient.read_multi_vars` / `write_multi_vars` send one request per item (a loop over
  `read_area`) and refuse more than `MAX_VARS` = 20 items.
- The sync `Client.read_multi_vars` refuses more than 20 items as well; its optimizer packs by
  PDU but decodes through `extract_multi_read_data` and blocks on sockets (an executor).
- `get_cpu_state` answers "S7CpuStatusRun" without asking (`extract_cpu_state` is a stub).

So the job header, the item count, the write data items and the per-item walk of a read reply
are built and read here, in the same wire format. bench/s7_libraries.py measures the choice.
"""

from __future__ import annotations

import struct
from typing import Any, cast

from snap7.datatypes import S7Area, S7DataTypes, S7WordLen
from snap7.s7protocol import S7Function, S7PDUType
from snap7.szl import parse_cpu_info_szl, parse_order_code_szl
from snap7.type import S7SZL

from ...errors import PlcAddressError, PlcError, PlcProtocolError, PlcWriteRefusedError
from .planner import Span, WriteItem

READ = S7Function.READ_AREA
WRITE = S7Function.WRITE_AREA
OK = 0xFF
TRANSPORT_BIT, TRANSPORT_BYTE, TRANSPORT_OCTETS = 0x03, 0x04, 0x09
_LENGTH_IN_BYTES = (0x03, 0x07, 0x09)  # bit (one byte), real, octet string; others count bits
SZL_IDENTITY = 0x001C
SZL_ORDER_CODE = 0x0011
SZL_STATE = 0x0424
# SZL 0x0424 bzu-id, bits 0..3: the mode the CPU is in (bits 4..7: the one before).
_MODES = {
    **dict.fromkeys((0x1, 0x2, 0x3, 0x4), "STOP"),  # update, memory reset, init, internal
    **dict.fromkeys((0x5, 0x6, 0x7), "STARTUP"),  # complete, cold and hot restart
    **dict.fromkeys((0x8, 0x9), "RUN"),  # RUN, RUN in a redundant (H) system
    0xA: "HOLD",
    0xD: "ERROR",  # DEFECT
}

_ITEM_ERRORS = {
    0x01: "hardware fault (is there a module at this address?)",
    0x03: "access denied (protection level, or a DB with optimized block access)",
    0x05: "address out of range (the area or DB is shorter)",
    0x06: "data type not supported at this address",
    0x07: "data type inconsistent with the address",
    0x0A: "no such object (the DB or area does not exist)",
}


def address_spec(span: Span, bit: int | None = None) -> bytes:
    """Return the 12-byte S7-ANY address spec of an item (a bit, bytes, or T/C elements)."""
    if span.counted:  # the area code doubles as word length; the address is the number
        word_length, count, start = span.area, span.length, span.start
    elif bit is not None:
        word_length, count, start = S7WordLen.BIT, 1, span.start * 8 + bit
    else:
        word_length, count, start = S7WordLen.BYTE, span.length, span.start
    # The library's enums lack 0x80 and 0x1E/0x1F; it packs the plain numbers all the same.
    area, length = cast(S7Area, span.area), cast(S7WordLen, word_length)
    return S7DataTypes.encode_address(area, span.db, start, length, count)


def _request(sequence: int, parameters: bytes, data: bytes = b"") -> bytes:
    """Return a job PDU: S7 header, parameters, data."""
    header = struct.pack(
        ">BBHHHH", 0x32, S7PDUType.REQUEST, 0, sequence, len(parameters), len(data)
    )
    return header + parameters + data


def read_request(sequence: int, spans: list[Span]) -> bytes:
    """Return one multi-variable read request for the spans."""
    specs = b"".join(address_spec(span) for span in spans)
    return _request(sequence, bytes([READ, len(spans)]) + specs)


def write_request(sequence: int, items: list[WriteItem]) -> bytes:
    """Return one multi-variable write request; a bit item carries transport size BIT."""
    specs = b"".join(address_spec(item.span, item.bit) for item in items)
    data = bytearray()
    for index, item in enumerate(items):
        if item.bit is not None:
            transport, length = TRANSPORT_BIT, 1
        elif item.span.counted:
            transport, length = TRANSPORT_OCTETS, len(item.data)
        else:
            transport, length = TRANSPORT_BYTE, len(item.data) * 8
        data += struct.pack(">BBH", 0, transport, length) + item.data
        if len(item.data) % 2 and index < len(items) - 1:
            data.append(0)
    return _request(sequence, bytes([WRITE, len(items)]) + specs, bytes(data))


class ShortAnswer(PlcProtocolError):
    """The PLC answered fewer items than the job asked (Snap7's server stops at 20)."""

    def __init__(self, answered: int, asked: int) -> None:
        """Keep how many items came back."""
        super().__init__(f"the PLC answered {answered} of {asked} items")
        self.answered = answered


def _check_function(response: dict[str, Any], function: int, count: int) -> bytes:
    """Return the reply's data section after checking it answers this function and count."""
    parameters = response.get("parameters") or {}
    answered = parameters.get("item_count")
    if parameters.get("function_code") == function and isinstance(answered, int):
        if answered < count:
            raise ShortAnswer(answered, count)
        if answered == count:
            raw = response.get("raw_data", b"")
            assert isinstance(raw, bytes)
            return raw
    raise PlcProtocolError(f"the PLC answered a {count}-item request with {answered} items")


def read_items(response: dict[str, Any], count: int) -> list[bytes | int]:
    """Return the data of each item of a read reply, or its return code when it failed."""
    raw = _check_function(response, READ, count)
    items: list[bytes | int] = []
    offset = 0
    for index in range(count):
        if offset + 4 > len(raw):
            raise PlcProtocolError(f"the PLC's read reply ends before item {index + 1}")
        code, transport, length = struct.unpack_from(">BBH", raw, offset)
        offset += 4
        if code != OK:
            items.append(code)  # a failed item carries no data
            continue
        size = length if transport in _LENGTH_IN_BYTES else length // 8
        if offset + size > len(raw):
            raise PlcProtocolError(f"the PLC's read reply cuts item {index + 1} short")
        items.append(raw[offset : offset + size])
        offset += size + (size % 2 if index < count - 1 else 0)
    return items


def write_codes(response: dict[str, Any], count: int) -> list[int]:
    """Return the return code of each item of a write reply."""
    raw = _check_function(response, WRITE, count)
    if len(raw) != count:
        raise PlcProtocolError(f"the PLC acknowledged {len(raw)} of {count} written items")
    return list(raw)


def item_error(code: int, address: str, *, write: bool = False) -> PlcError:
    """Return the error of one item from its return code (0x0A, 0x05, ...)."""
    text = _ITEM_ERRORS.get(code)
    if text is None:
        return PlcProtocolError(f"{address}: the PLC answered the item with code 0x{code:02X}")
    if write and code == 0x03:
        return PlcWriteRefusedError(f"{address}: the PLC refused the write: {text}")
    return PlcAddressError(f"{address}: {text} (0x{code:02X})")


def cpu_mode(szl: bytes) -> str | None:
    """Return RUN, STOP, STARTUP, HOLD or ERROR (DEFECT) from SZL 0x0424; None when unknown.

    Byte 3 of the record (after the 4-byte list header) is the bzu-id; its low nibble is the
    mode the CPU is in. Snap7 (the C library) compares the whole byte with 0x08 and calls
    anything else STOP, a STARTUP or HOLD included.
    """
    if len(szl) < 8:
        raise PlcProtocolError("the PLC's CPU state list (SZL 0x0424) is too short")
    return _MODES.get(szl[7] & 0x0F)


def _szl(data: bytes) -> S7SZL:
    """Wrap list bytes (header and records) in the structure python-snap7's parsers take."""
    szl = S7SZL()
    data = data[: len(szl.Data)]
    szl.Data[: len(data)] = data
    szl.Header.LengthDR = len(data)
    szl.Header.NDR = 1
    return szl


def _text(raw: bytes) -> str:
    """Return a fixed-length SZL text field without padding."""
    return raw.decode("latin-1").strip("\x00 ")


def identity(order_code: bytes | None, component: bytes | None) -> dict[str, str]:
    """Return what SZL 0x0011 (order code, firmware) and 0x001C (names, serial) say."""
    found: dict[str, str] = {}
    if order_code:
        order = parse_order_code_szl(_szl(order_code))
        found["order_code"] = _text(order.OrderCode)
        if order.V1 or order.V2 or order.V3:
            found["firmware"] = f"V{order.V1}.{order.V2}.{order.V3}"
    if component:
        info = parse_cpu_info_szl(_szl(component))
        found["module_type"] = _text(info.ModuleTypeName)
        found["serial"] = _text(info.SerialNumber)
        found["name"] = _text(info.ASName)
        found["module_name"] = _text(info.ModuleName)
    return {key: value for key, value in found.items() if value}
