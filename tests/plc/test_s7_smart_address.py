"""S7-200 SMART addresses, value checks, wire codec and request planning (no sockets)."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any
from zoneinfo import ZoneInfo

import pytest

from custom_components.plc_bridge.plc import (
    PlcAddressError,
    PlcProtocolError,
    PlcStatus,
    PlcValueError,
    PlcWriteRefusedError,
    Point,
)
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from custom_components.plc_bridge.plc.vendors.s7_smart.address import parse_address, point_kind
from custom_components.plc_bridge.plc.vendors.s7_smart.codec import (
    decode,
    decode_status,
    encode,
    node_for,
)
from custom_components.plc_bridge.plc.vendors.s7_smart.errors import (
    STOP_MESSAGE,
    RpcError,
    node_error,
    request_error,
)
from custom_components.plc_bridge.plc.vendors.s7_smart.rpc import cookie_header, retry_after

PRAGUE = ZoneInfo("Europe/Prague")


@pytest.mark.parametrize(
    ("text", "normalized", "width"),
    [
        ("v10.3", "V10.3", 1),
        ("VB0", "VB0", 8),
        (" vw020 ", "VW20", 16),
        ("Vd20476", "VD20476", 32),
        ("i0.0", "I0.0", 1),
        ("IB31", "IB31", 8),
        ("qd28", "QD28", 32),
        ("m31.7", "M31.7", 1),
        ("MW30", "MW30", 16),
        ("SMB1535", "SMB1535", 8),
        ("sm0.0", "SM0.0", 1),
        ("smw0", "SMW0", 16),
        ("aiw0", "AIW0", 16),
        ("AQW110", "AQW110", 16),
        ("t255", "T255", 16),
        ("c0", "C0", 16),
        ("hc5", "HC5", 32),
        ("date", "DATE", 0),
    ],
)
def test_valid_addresses(text: str, normalized: str, width: int) -> None:
    address = parse_address(text)
    assert (address.text, address.width) == (normalized, width)
    assert S7SmartClient.validate_point(Point(text, "Signed")) == Point(normalized, "signed")


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("VW70000", "VW70000 is outside V memory (0..20479)"),
        ("VD20477", "VD20477 runs past the end of V memory (0..20479); it needs 4 bytes"),
        ("v10.8", "V10.8 names bit 8; bits are 0..7"),
        ("IB32", "IB32 is outside process inputs (I) (0..31)"),
        ("QW31", "QW31 runs past the end of process outputs (Q)"),
        ("M32.0", "M32.0 is outside M memory (0..31)"),
        ("SMD1533", "SMD1533 runs past the end of special memory (SM)"),
        ("AIW3", "AIW3 is not a word address; analog inputs (AIW) are even numbers (0, 2, .. 110)"),
        ("AQW112", "AQW112 is outside analog outputs (AQW) (0..110)"),
        ("T256", "T256 is outside timers (T) (0..255)"),
        ("C300", "C300 is outside counters (C) (0..255)"),
        ("HC6", "HC6 is outside high-speed counters (HC) (0..5)"),
        ("X1", "'X1' is not an S7-200 SMART address; try V10.3"),
        ("VB", "not an S7-200 SMART address"),
        ("V1.2.3", "not an S7-200 SMART address"),
        ("", "not an S7-200 SMART address"),
        ("DB1.DBX0.0", "not an S7-200 SMART address"),
    ],
)
def test_invalid_addresses(text: str, message: str) -> None:
    with pytest.raises(PlcAddressError) as caught:
        S7SmartClient.validate_point(Point(text, "signed"))
    assert message in str(caught.value)


@pytest.mark.parametrize(
    ("address", "mode", "message"),
    [
        ("VW0", "float", "VW0 cannot hold a float; a REAL needs a double word"),
        ("VB0", "float", "cannot hold a float"),
        ("HC0", "float", "HC0 cannot hold a float"),
        ("VW0", "string", "VW0 cannot hold a string; strings start at a byte"),
        ("T0", "string", "cannot hold a string"),
        ("VB0", "bogus", "unknown data type 'bogus'; use one of signed, unsigned, float"),
        ("V0.0", "bool", "unknown data type 'bool'"),
    ],
)
def test_mode_and_width(address: str, mode: str, message: str) -> None:
    with pytest.raises(PlcAddressError, match=message):
        S7SmartClient.validate_point(Point(address, mode))


def test_kinds() -> None:
    assert point_kind(parse_address("V0.0"), "float") == "bool"
    assert point_kind(parse_address("DATE"), "string") == "date"
    assert point_kind(parse_address("VD0"), " FLOAT ") == "float"
    assert point_kind(parse_address("T3"), "raw") == "raw"
    assert S7SmartClient.validate_point(Point("vd0", " Float ")) == Point("VD0", "float")


@pytest.mark.parametrize(
    ("address", "mode", "value", "expected"),
    [
        ("VB0", "signed", -128, -128),
        ("VB0", "unsigned", "255", 255),
        ("VW0", "signed", 32767.0, 32767),
        ("VD0", "unsigned", 2**32 - 1, 2**32 - 1),
        ("T1", "signed", -5, -5),
        ("HC1", "signed", -(2**31), -(2**31)),
        ("VD0", "float", "1.5", 1.5),
        ("VB0", "string", "x" * 254, "x" * 254),
        ("VB20470", "string", "x" * 9, "x" * 9),
        ("V0.0", "signed", "on", True),
        ("Q0.1", "raw", 0, False),
        ("VW0", "raw", [1, 255], [1, 255]),
        ("HC0", "raw", [0, 0, 0, 1], [0, 0, 0, 1]),
        ("DATE", "signed", "2024-02-29T10:00:00", datetime(2024, 2, 29, 10)),
    ],
)
def test_values_accepted(address: str, mode: str, value: Any, expected: Any) -> None:
    assert S7SmartClient.validate_value(Point(address, mode), value) == expected


@pytest.mark.parametrize(
    ("address", "mode", "value", "message"),
    [
        ("VB0", "signed", 128, "VB0 128 is outside -128..127"),
        ("VB0", "unsigned", -1, "outside 0..255"),
        ("VW0", "signed", 1.5, "whole number"),
        ("VD0", "unsigned", 2**32, "outside 0..4294967295"),
        ("VD0", "float", float("inf"), "does not fit a REAL"),
        ("VD0", "float", 1e39, "does not fit a REAL"),
        ("VD0", "float", "abc", "must be a number"),
        ("VB0", "string", "é", "ASCII characters only"),
        ("VB0", "string", "x" * 255, "longer than 254 characters"),
        ("VB20470", "string", "x" * 10, "longer than 9 characters"),
        ("V0.0", "signed", 2, "true or false"),
        ("VW0", "raw", [1], "VW0 takes a list of 2 byte values"),
        ("VW0", "raw", [256, 0], "list of 2 byte values"),
        ("VW0", "raw", [True, 0], "list of 2 byte values"),
        ("VB0", "raw", "x", "list of 1 byte values"),
        ("DATE", "signed", "yesterday", "DATE must be a date and time"),
        ("DATE", "signed", 5, "DATE must be a date and time"),
        ("DATE", "signed", datetime(1999, 12, 31), "years 2000..2099"),
    ],
)
def test_values_refused(address: str, mode: str, value: Any, message: str) -> None:
    with pytest.raises(PlcValueError, match=message):
        S7SmartClient.validate_value(Point(address, mode), value)


def test_requests_for() -> None:
    words = [Point(f"VW{2 * i}", "signed") for i in range(100)]
    assert S7SmartClient.requests_for([]) == 1  # a poll without points still reads the status
    assert S7SmartClient.requests_for([Point("X", "signed")]) == 1
    assert [S7SmartClient.requests_for(words[:n]) for n in (1, 32, 33, 64, 100)] == [1, 1, 2, 2, 4]
    same = [Point("VW0", "signed"), Point("vw0", "signed"), Point("V0.1", "raw")] * 40
    assert S7SmartClient.requests_for(same) == 1


def test_cookie_header() -> None:
    assert cookie_header("Session-Id=YWRtaW4uKdPE+HWZqrhQ==") == "Session-Id=YWRtaW4uKdPE+HWZqrhQ=="
    assert cookie_header("YWRtaW4uKdPE+HWZqrhQ==") == "Session-Id=YWRtaW4uKdPE+HWZqrhQ=="
    assert cookie_header("abc") == "Session-Id=abc"


@pytest.mark.parametrize(
    ("address", "kind", "raw", "expected"),
    [
        ("V0.0", "bool", 1, True),
        ("VW0", "signed", -2, -2),
        ("VW0", "unsigned", 65535, 65535),
        ("VD0", "float", 3, 3.0),
        ("VB0", "string", "ab", "ab"),
        ("VW0", "raw", [1, 2], [1, 2]),
        ("DATE", "date", "2024-01-02 03:04:05", datetime(2024, 1, 2, 3, 4, 5, tzinfo=PRAGUE)),
    ],
)
def test_decode(address: str, kind: str, raw: Any, expected: Any) -> None:
    assert decode(parse_address(address), kind, raw, PRAGUE) == expected


@pytest.mark.parametrize(
    ("address", "kind", "raw"),
    [
        ("V0.0", "bool", 2),
        ("V0.0", "bool", True),
        ("VW0", "signed", 40000),
        ("VW0", "signed", 1.5),
        ("VW0", "signed", "7"),
        ("VD0", "float", None),
        ("VB0", "string", 5),
        ("VW0", "raw", [1]),
        ("VW0", "raw", "ab"),
        ("DATE", "date", "02.01.2024"),
        ("DATE", "date", None),
    ],
)
def test_decode_refuses(address: str, kind: str, raw: Any) -> None:
    with pytest.raises(PlcProtocolError, match=f"{address}: the PLC sent"):
        decode(parse_address(address), kind, raw, PRAGUE)


def test_encode() -> None:
    assert encode("bool", True, PRAGUE) == 1
    assert encode("bool", False, PRAGUE) == 0
    assert encode("date", datetime(2025, 1, 1, 12, tzinfo=UTC), PRAGUE) == "2025-01-01 13:00:00"
    assert encode("date", datetime(2025, 7, 1, 12), PRAGUE) == "2025-07-01 12:00:00"
    assert encode("raw", [1, 2], PRAGUE) == [1, 2]


def test_decode_status() -> None:
    status = {
        "Date": "2024-05-06 07:08:09",
        "Operating Mode": "STOP",
        "System Status": "Error",
        "Force Status": "Forced",
    }
    assert decode_status(status, PRAGUE) == PlcStatus(
        mode="STOP",
        system="Error",
        force="Forced",
        clock=datetime(2024, 5, 6, 7, 8, 9, tzinfo=PRAGUE),
    )
    assert decode_status(None, PRAGUE) == PlcStatus()
    assert decode_status({}, PRAGUE) == PlcStatus()
    assert decode_status({"Date": "soon", "Operating Mode": 1}, PRAGUE) == PlcStatus()


@pytest.mark.parametrize(
    ("code", "message", "write", "kind", "text"),
    [
        # No code decides the kind or lends a meaning: the PLC's words, behind a neutral lead.
        (1003, "Permission denied.", True, PlcWriteRefusedError, "the PLC refused the write"),
        (2001, "CPU not in RUN.", False, PlcProtocolError, "the PLC refused the request"),
        (1002, "Too many nodes.", False, PlcProtocolError, "the PLC refused the request"),
    ],
)
def test_request_errors(
    code: int, message: str, write: bool, kind: type[Exception], text: str
) -> None:
    error = request_error(RpcError(code, message), write=write)
    assert isinstance(error, kind)
    assert str(error) == f"{text} ({message}, code {code})"
    assert str(request_error(RpcError(77, ""), write=False)).endswith("(no message, code 77)")


def test_node_errors() -> None:
    """Only 3004 is the manual's; any other code is the PLC refusing the node, in its words."""
    assert str(node_error(3004, "VB9", "Invalid address.")) == (
        "VB9: the PLC has no such address (code 3004)"
    )
    assert str(node_error(3004, "VB9", "No such area")) == (
        "VB9: the PLC has no such address (No such area, code 3004)"
    )
    read_only = node_error(3005, "SMB0", "Address is read only", write=True)
    assert isinstance(read_only, PlcWriteRefusedError)
    assert str(read_only) == "SMB0: the PLC refused it (Address is read only, code 3005)"
    in_stop = node_error(3006, "VW0", "CPU is not in RUN mode", write=True, stopped=True)
    assert isinstance(in_stop, PlcWriteRefusedError)
    assert str(in_stop) == f"VW0: {STOP_MESSAGE} (CPU is not in RUN mode, code 3006)"
    unknown = node_error(None, "VB9")
    assert isinstance(unknown, PlcProtocolError)
    assert str(unknown) == "VB9: the PLC refused it (no message, code None)"
    assert len(str(node_error([[[[[[[[1]]]]]]]], "VB9"))) < 80  # never the whole of a value


@pytest.mark.parametrize(
    ("header", "seconds"),
    [
        ({"Retry-After": "3"}, 3.0),
        ({"Retry-After": "86400"}, 60.0),  # bounded
        ({"Retry-After": "9" * 5000}, 60.0),
        ({"Retry-After": "Thu, 01 Jan 2026 00:00:20 GMT"}, 20.0),
        ({"Retry-After": "Wed, 31 Dec 2025 23:00:00 GMT"}, 0.0),  # already past
        ({"Retry-After": "soon"}, 2.0),
        ({}, 2.0),
    ],
)
def test_retry_after(header: dict[str, str], seconds: float) -> None:
    assert retry_after(header, datetime(2026, 1, 1, tzinfo=UTC)) == seconds


def test_node_cache_holds_a_large_poll() -> None:
    """A 10,000-point poll planned again parses nothing again (a cache of 4,096 parsed all)."""
    points = [Point(f"VB{index}", "unsigned") for index in range(10_000)]
    for point in points:
        node_for(point)
    hits = node_for.cache_info().hits
    for point in points:
        node_for(point)
    assert node_for.cache_info().hits - hits == len(points)
