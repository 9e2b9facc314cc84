"""S7 values and PDUs: decode, encode, multi-variable requests, item codes, SZL. No sockets."""

from __future__ import annotations

from datetime import UTC, datetime
import math
import struct
from zoneinfo import ZoneInfo

import pytest
from snap7.s7protocol import S7Protocol

from custom_components.plc_bridge.plc import (
    PlcAddressError,
    PlcProtocolError,
    PlcValueError,
    PlcWriteRefusedError,
    Point,
    Value,
)
from custom_components.plc_bridge.plc.vendors.s7.address import (
    AREA_C,
    AREA_C200,
    AREA_DB,
    AREA_P,
    AREA_T200,
    variable,
)
from custom_components.plc_bridge.plc.vendors.s7.codec import (
    decode,
    encode,
    plc_time,
    real,
    write_items,
)
from custom_components.plc_bridge.plc.vendors.s7.planner import Span, WriteItem
from custom_components.plc_bridge.plc.vendors.s7.protocol import (
    ShortAnswer,
    address_spec,
    cpu_mode,
    identity,
    item_error,
    read_items,
    read_request,
    write_codes,
    write_request,
)

PRAGUE = ZoneInfo("Europe/Prague")

ROUND_TRIPS: list[tuple[str, str, Value, bytes]] = [
    ("DB1.DBX0.3", "BOOL", True, b"\x01"),
    ("DB1.DBB0", "BYTE", 0xAB, b"\xab"),
    ("DB1.DBB0", "CHAR", "Z", b"Z"),
    ("DB1.DBW0", "WORD", 0x1234, b"\x12\x34"),
    ("DB1.DBW0", "INT", -2, b"\xff\xfe"),
    ("DB1.DBW0", "UINT", 65535, b"\xff\xff"),
    ("DB1.DBD0", "DWORD", 0xDEADBEEF, b"\xde\xad\xbe\xef"),
    ("DB1.DBD0", "DINT", -(2**31), b"\x80\x00\x00\x00"),
    ("DB1.DBD0", "UDINT", 2**32 - 1, b"\xff\xff\xff\xff"),
    ("DB1.DBD0", "REAL", 21.3, struct.pack(">f", 21.3)),
    ("DB1.DBB0", "LREAL", -0.1, struct.pack(">d", -0.1)),
    ("DB1.DBB0", "STRING[5]", "héllo", b"\x05h\xe9llo"),
    ("DB1.DBB0", "STRING", "", b"\x00"),
    (
        "DB1.DBB0",
        "DATE_AND_TIME",
        datetime(2024, 7, 12, 17, 32, 2, 854000, tzinfo=PRAGUE),
        bytes([0x24, 0x07, 0x12, 0x17, 0x32, 0x02, 0x85, 0x46]),
    ),
    (
        "DB1.DBB0",
        "DTL",
        datetime(2024, 3, 27, 14, 30, 0, 5, tzinfo=PRAGUE),
        b"\x07\xe8\x03\x1b\x04\x0e\x1e\x00\x00\x00\x13\x88",
    ),
]


@pytest.mark.parametrize(("address", "data_type", "value", "raw"), ROUND_TRIPS)
def test_encode_decode(address: str, data_type: str, value: Value, raw: bytes) -> None:
    found = variable(Point(address, data_type))
    assert encode(found, value, PRAGUE) == raw
    stored = bytes([found.string_length]) + raw if found.string_length else raw
    stored = stored.ljust(found.size, b"\x00")
    if data_type == "BOOL":
        stored = bytes([1 << 3])
    assert decode(found, stored, PRAGUE) == value


def test_decode_details() -> None:
    assert decode(variable(Point("M0.3", "BOOL")), b"\xf7", PRAGUE) is False
    assert real(struct.pack(">f", 16777216.0)) == 16777216.0
    assert math.isnan(real(b"\x7f\xc0\x00\x00"))
    text = variable(Point("DB1.DBB0", "STRING[4]"))
    assert decode(text, b"\x00\x00abcd", PRAGUE) == ""  # a never-written STRING
    with pytest.raises(PlcProtocolError, match="holds a STRING of 9 characters"):
        decode(text, b"\xfe\x09abcd", PRAGUE)
    with pytest.raises(PlcProtocolError, match="does not hold a valid DATE_AND_TIME"):
        decode(variable(Point("DB1.DBB0", "DT")), bytes(8), PRAGUE)  # month 0
    with pytest.raises(PlcProtocolError, match="valid DATE_AND_TIME"):
        decode(variable(Point("DB1.DBB0", "DT")), bytes([0x2A, 1, 1, 0, 0, 0, 0, 1]), PRAGUE)
    with pytest.raises(PlcProtocolError, match="valid DTL"):
        decode(variable(Point("DB1.DBB0", "DTL")), bytes(12), PRAGUE)


def test_plc_time() -> None:
    aware = datetime(2025, 1, 1, 12, 0, tzinfo=UTC)
    assert plc_time(aware, PRAGUE, 1990, 2089, "x") == datetime(2025, 1, 1, 13, 0)
    assert plc_time(datetime(2025, 1, 1), PRAGUE, 1990, 2089, "x") == datetime(2025, 1, 1)
    with pytest.raises(PlcValueError, match=r"DB1\.DBB0 holds years 1990\.\.2089, not 2100"):
        encode(variable(Point("DB1.DBB0", "DT")), datetime(2100, 1, 1), PRAGUE)


def test_write_items() -> None:
    bit = write_items(variable(Point("DB2.DBX3.5", "BOOL")), True, PRAGUE, 480)
    assert bit == [WriteItem(Span(AREA_DB, 2, 3, 1), b"\x01", 5)]
    text = write_items(variable(Point("DB1.DBB10", "STRING[20]")), "ab", PRAGUE, 480)
    assert text == [WriteItem(Span(AREA_DB, 1, 11, 3), b"\x02ab")]  # max-length byte untouched
    long = write_items(variable(Point("DB1.DBB0", "STRING")), "x" * 254, PRAGUE, 240)
    assert [item.span for item in long] == [Span(AREA_DB, 1, 1, 212), Span(AREA_DB, 1, 213, 43)]
    counter = write_items(variable(Point("C7", "WORD")), 0x0123, PRAGUE, 240)
    assert counter == [WriteItem(Span(AREA_C, 0, 7, 1), b"\x01\x23")]


def test_address_specs() -> None:
    assert address_spec(Span(AREA_DB, 1, 2, 4)).hex() == "120a10020004000184000010"
    assert address_spec(Span(AREA_DB, 1, 2, 1), bit=7).hex() == "120a10010001000184000017"
    assert address_spec(Span(AREA_C, 0, 5, 2)).hex() == "120a101c000200001c000005"
    assert address_spec(Span(AREA_P, 0, 256, 2)).hex() == "120a10020002000080000800"
    assert address_spec(Span(AREA_T200, 0, 5, 1)).hex() == "120a101f000100001f000005"


def test_address_specs_as_hand_packed() -> None:
    """python-snap7's encode_address gives the bytes the S7-ANY format defines, for every kind."""
    for area, db, start, length, bit in [
        (AREA_DB, 65535, 65534, 2, None),
        (AREA_DB, 3, 100, 1, 6),
        (AREA_P, 0, 512, 4, None),
        (AREA_C, 0, 255, 3, None),
        (AREA_C200, 0, 7, 1, None),
    ]:
        counted = area in (AREA_C, AREA_C200)
        word_length = area if counted else 0x01 if bit is not None else 0x02
        where = start if counted else start * 8 + (bit or 0)
        count = 1 if bit is not None else length
        hand = struct.pack(">BBBBHHB", 0x12, 0x0A, 0x10, word_length, count, db, area)
        assert address_spec(Span(area, db, start, length), bit) == hand + where.to_bytes(3)


def test_peripheral_inputs_are_not_written() -> None:
    with pytest.raises(PlcValueError, match="PIW256: peripheral inputs cannot be written"):
        encode(variable(Point("PIW256", "WORD")), 1, PRAGUE)
    assert encode(variable(Point("PQW256", "WORD")), 1, PRAGUE) == b"\x00\x01"


def test_read_request() -> None:
    pdu = read_request(7, [Span(AREA_DB, 1, 2, 4), Span(AREA_P, 0, 256, 2)])
    assert pdu[:10].hex() == "320100000007001a0000"
    assert pdu[10:12] == b"\x04\x02"
    assert len(pdu) == 10 + 2 + 2 * 12


def test_write_request() -> None:
    items = [
        WriteItem(Span(AREA_DB, 1, 3, 1), b"\x01", 2),
        WriteItem(Span(AREA_DB, 1, 10, 3), b"abc"),
        WriteItem(Span(AREA_C, 0, 1, 1), b"\x00\x05"),
    ]
    pdu = write_request(9, items)
    parameters, data = pdu[10 : 10 + 2 + 36], pdu[10 + 38 :]
    assert pdu[6:10] == struct.pack(">HH", 38, len(data))
    assert parameters[:2] == b"\x05\x03"
    assert data.hex() == "000300010100" + "0004001861626300" + "000900020005"  # fill bytes


def reply(function: int, count: int, data: bytes) -> dict[str, object]:
    """Parse a reply PDU the way the client does (python-snap7's parser)."""
    header = struct.pack(">BBHHHHBB", 0x32, 3, 0, 1, 2, len(data), 0, 0)
    return S7Protocol().parse_response(header + bytes([function, count]) + data)


def test_read_items() -> None:
    data = b"\xff\x04\x00\x18abc\x00" + b"\x0a\x00\x00\x00" + b"\xff\x09\x00\x02TT"
    assert read_items(reply(4, 3, data), 3) == [b"abc", 0x0A, b"TT"]
    assert read_items(reply(4, 1, b"\x05\x00\x00\x00"), 1) == [0x05]
    assert read_items(reply(4, 1, b"\xff\x03\x00\x01\x01"), 1) == [b"\x01"]  # a bit
    with pytest.raises(PlcProtocolError, match="answered a 2-item request with 3 items"):
        read_items(reply(4, 3, data), 2)
    with pytest.raises(ShortAnswer, match="answered 3 of 5 items") as short:
        read_items(reply(4, 3, data), 5)  # fewer items than asked: none of them is used
    assert short.value.answered == 3
    with pytest.raises(PlcProtocolError, match="ends before item 2"):
        read_items(reply(4, 2, b"\xff\x04\x00\x10ab"), 2)
    with pytest.raises(PlcProtocolError, match="cuts item 1 short"):
        read_items(reply(4, 2, b"\xff\x04\x00\x30ab"), 2)


def test_write_codes() -> None:
    assert write_codes(reply(5, 3, b"\xff\x0a\xff"), 3) == [0xFF, 0x0A, 0xFF]
    with pytest.raises(PlcProtocolError, match="acknowledged 2 of 3"):
        write_codes(reply(5, 3, b"\xff\x0a"), 3)
    with pytest.raises(ShortAnswer, match="answered 2 of 3 items"):
        write_codes(reply(5, 2, b"\xff\x0a"), 3)


def test_item_errors() -> None:
    assert isinstance(item_error(0x0A, "DB9.DBW0"), PlcAddressError)
    assert str(item_error(0x0A, "DB9.DBW0")) == (
        "DB9.DBW0: no such object (the DB or area does not exist) (0x0A)"
    )
    assert "out of range" in str(item_error(0x05, "DB1.DBW600"))
    assert isinstance(item_error(0x03, "MW0"), PlcAddressError)
    refused = item_error(0x03, "MW0", write=True)
    assert isinstance(refused, PlcWriteRefusedError)
    assert "protection level" in str(refused)
    assert isinstance(item_error(0x01, "PIW512"), PlcAddressError)
    unknown = item_error(0x42, "MW0")
    assert type(unknown) is PlcProtocolError
    assert "code 0x42" in str(unknown)


@pytest.mark.parametrize(
    ("bzu_id", "mode"),
    [
        (0x08, "RUN"),
        (0x58, "RUN"),  # bits 4..7 hold the mode before (here STARTUP)
        (0x09, "RUN"),  # RUN in a redundant (H) system
        (0x04, "STOP"),
        (0x03, "STOP"),  # older CPUs
        (0x01, "STOP"),
        (0x05, "STARTUP"),
        (0x87, "STARTUP"),
        (0x0A, "HOLD"),
        (0x0D, "ERROR"),  # DEFECT
        (0x0B, None),  # link-up of an H system: no mode to show, and surely no STOP
        (0x0F, None),
        (0x00, None),
    ],
)
def test_cpu_mode(bzu_id: int, mode: str | None) -> None:
    head = struct.pack(">HHHB", 20, 1, 0x4302, 0xFF)
    assert cpu_mode(head + bytes([bzu_id]) + bytes(16)) == mode


def test_cpu_mode_too_short() -> None:
    with pytest.raises(PlcProtocolError, match="too short"):
        cpu_mode(struct.pack(">HHHB", 20, 1, 0x4302, 0xFF))


def test_identity() -> None:
    assert identity(None, None) == {}
    order = (
        struct.pack(">HH", 28, 1)
        + b"\x00\x01"
        + b"6ES7 214-1AG40-0XB0 "
        + bytes([0, 4, 2, 1, 0, 0])
    )
    assert identity(order, None) == {"order_code": "6ES7 214-1AG40-0XB0", "firmware": "V4.2.1"}
    records = {1: b"Line 3", 2: b"PLC_1", 5: b"S V-L9AB1234", 7: b"CPU 1214C DC/DC/DC"}
    component = struct.pack(">HH", 34, 6) + b"".join(
        index.to_bytes(2, "big") + records.get(index, b"").ljust(32, b"\x00")
        for index in (1, 2, 3, 4, 5, 7)
    )
    assert identity(None, component) == {
        "name": "Line 3",
        "module_name": "PLC_1",
        "serial": "S V-L9AB1234",
        "module_type": "CPU 1214C DC/DC/DC",
    }
