"""S7 values: checked before sending, decoded from and encoded to the PLC's big-endian bytes."""

from __future__ import annotations

from datetime import datetime, tzinfo
from functools import lru_cache
import struct

from snap7.util import get_date_time_object, get_dtl, set_dt, set_dtl

from ...codec import (
    CHECKED,
    INTEGER_RANGES,
    check_iec,
    local_time,
    shortest_real,
)
from ...errors import PlcProtocolError, PlcValueError
from ...types import Value
from .address import AREA_P, Variable
from .planner import Span, WriteItem, write_pieces
from .times import TIMES, check_time, decode_time, encode_time

SIGNED = ("SINT", "INT", "DINT", "LINT")
YEARS = {"DATE_AND_TIME": (1990, 2089), "DTL": (1970, 2554)}


@lru_cache(maxsize=8192)
def span_of(variable: Variable) -> Span:
    """The range a variable is read from (timers and counters: one element)."""
    length = 1 if variable.counted else variable.size
    return Span(variable.area, variable.db, variable.start, length)


def check_value(variable: Variable, value: Value) -> Value:
    """Return the value coerced to the variable's type; raise PlcValueError."""
    what, kind = variable.text, variable.data_type
    if variable.area == AREA_P and not variable.write_area:
        # A write to area 0x80 reaches the peripheral outputs of the same address.
        raise PlcValueError(f"{what}: peripheral inputs cannot be written")
    if kind in TIMES:  # before the IEC checks: an S7 DATE runs from 1990 to 2168 only
        return check_time(kind, value, what)
    if kind in CHECKED:
        return check_iec(kind, value, what)
    if kind in YEARS:
        return _datetime(value, what)
    if not isinstance(value, str):
        raise PlcValueError(f"{what} takes text, not {value!r}")
    wide = kind == "WCHAR" or variable.wide
    try:
        length = len(value.encode("utf-16-be" if wide else "latin-1")) // (2 if wide else 1)
    except UnicodeEncodeError:
        raise PlcValueError(
            f"{what}: S7 {'wide text holds Unicode' if wide else 'text holds Latin-1'} "
            "characters only"
        ) from None
    single = kind in ("CHAR", "WCHAR")
    if (single and length != 1) or length > (1 if single else variable.string_length):
        raise PlcValueError(
            f"{what} takes exactly one character"
            if single
            else f"{what} holds at most {variable.string_length} characters"
        )
    return value


def _datetime(value: Value, what: str) -> datetime:
    """Return a datetime from a datetime or an ISO 8601 text."""
    if isinstance(value, datetime):
        return value
    if isinstance(value, str):
        try:
            return datetime.fromisoformat(value.strip())
        except ValueError:
            pass
    raise PlcValueError(f"{what} takes a date and time, not {value!r}")


def decode(variable: Variable, data: bytes, zone: tzinfo) -> Value:
    """Return the value of a variable from its bytes; raise PlcProtocolError for bad content."""
    try:
        return _decode(variable, data, zone)
    except (struct.error, IndexError) as err:  # fewer bytes than the type holds
        raise PlcProtocolError(
            f"{variable.text}: the PLC answered {len(data)} bytes,"
            f" too few for a {variable.data_type}"
        ) from err


def _decode(variable: Variable, data: bytes, zone: tzinfo) -> Value:
    """Decode the bytes of a variable (the reader checked their count; this never trusts it)."""
    kind = variable.data_type
    if kind == "BOOL":
        return bool(data[0] >> (variable.bit or 0) & 1)
    if kind in INTEGER_RANGES:
        return int.from_bytes(data, "big", signed=kind in SIGNED)
    if kind == "REAL":
        return real(data)
    if kind == "LREAL":
        return float(struct.unpack(">d", data)[0])
    if kind == "CHAR":
        return data.decode("latin-1")
    if kind in YEARS:
        return _decode_datetime(variable, data, zone)
    if kind in TIMES:
        return decode_time(kind, data, zone, variable.text)
    if kind == "WCHAR":
        return _wide(variable, data[:2])
    wide = variable.wide
    header = variable.header_size // 2
    maximum = int.from_bytes(data[:header], "big")
    length = int.from_bytes(data[header : 2 * header], "big")
    if length > min(maximum, variable.string_length):
        raise PlcProtocolError(
            f"{variable.text} holds a {'W' if wide else ''}STRING of {length} characters "
            f"(maximum {maximum}), which does not fit {kind}: give the length it is declared with"
        )
    text = data[2 * header : 2 * header + length * (2 if wide else 1)]
    return _wide(variable, text) if wide else text.decode("latin-1")


def _wide(variable: Variable, data: bytes) -> str:
    """Return UTF-16BE text; raise PlcProtocolError for a cut or unpaired code unit."""
    try:
        return data.decode("utf-16-be")
    except UnicodeDecodeError:
        raise PlcProtocolError(
            f"{variable.text} holds no UTF-16 text ({data[:8].hex(' ')})"
        ) from None


def real(data: bytes) -> float:
    """Return a REAL as the shortest decimal of the same 32-bit float (21.3, not 21.2999...)."""
    return shortest_real(float(struct.unpack(">f", data)[0]))


def _decode_datetime(variable: Variable, data: bytes, zone: tzinfo) -> datetime:
    """Decode DATE_AND_TIME (BCD) or DTL (binary) in the PLC's time zone."""
    try:
        if variable.data_type == "DATE_AND_TIME":
            if any(byte >> 4 > 9 or byte & 0x0F > 9 for byte in data[:7]) or data[7] >> 4 > 9:
                raise ValueError("not BCD")
            value = get_date_time_object(bytearray(data), 0)
        else:
            value = get_dtl(bytearray(data), 0)
    except ValueError:
        raise PlcProtocolError(
            f"{variable.text} does not hold a valid {variable.data_type} ({data.hex(' ')})"
        ) from None
    return value.replace(tzinfo=zone)


def plc_time(value: datetime, zone: tzinfo, low: int, high: int, what: str) -> datetime:
    """Return an aware time as naive PLC local time (a naive one is taken as is)."""
    local = local_time(value, zone).replace(tzinfo=None)
    if not low <= local.year <= high:
        raise PlcValueError(f"{what} holds years {low}..{high}, not {local.year}")
    return local


def encode(variable: Variable, value: Value, zone: tzinfo) -> bytes:
    """Return the bytes of a checked value (STRING: length byte and text)."""
    kind = variable.data_type
    value = check_value(variable, value)
    if kind == "BOOL":
        return b"\x01" if value else b"\x00"
    if kind in INTEGER_RANGES:
        assert isinstance(value, int)
        return value.to_bytes(variable.size, "big", signed=kind in SIGNED)
    if kind in ("REAL", "LREAL"):
        assert isinstance(value, float)
        return struct.pack(">f" if kind == "REAL" else ">d", value)
    if kind in YEARS:
        assert isinstance(value, datetime)
        local = plc_time(value, zone, *YEARS[kind], what=variable.text)
        buffer = bytearray(variable.size)
        (set_dt if kind == "DATE_AND_TIME" else set_dtl)(buffer, 0, local)
        return bytes(buffer)
    if kind in TIMES:
        return encode_time(kind, value, zone, variable.text)
    assert isinstance(value, str)
    if kind == "WCHAR" or variable.wide:
        text = value.encode("utf-16-be")
        return text if kind == "WCHAR" else (len(text) // 2).to_bytes(2, "big") + text
    text = value.encode("latin-1")
    return text if kind == "CHAR" else bytes([len(text)]) + text


def write_items(variable: Variable, value: Value, zone: tzinfo, pdu_size: int) -> list[WriteItem]:
    """Return the write items of one value, cut to what a request of this PDU carries."""
    data = encode(variable, value, zone)
    span = span_of(variable)
    if variable.write_area:
        span = Span(variable.write_area, span.db, span.start, span.length)
    if variable.bit is not None:
        return [WriteItem(span, data, variable.bit)]
    if variable.string_length:
        # Skip the maximum length: the PLC's declaration owns it, a wrong [n] must not
        # overwrite it; write the current length and the characters only.
        skip = variable.header_size // 2
        span = Span(span.area, span.db, span.start + skip, len(data))
    return write_pieces(span, data, pdu_size)
