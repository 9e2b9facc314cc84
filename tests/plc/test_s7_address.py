"""S7 addresses, data types, options and value checks: pure, no sockets."""

from __future__ import annotations

from datetime import datetime
from typing import Any

import pytest

from custom_components.plc_bridge.plc import (
    ConnectionConfig,
    PlcAddressError,
    PlcValueError,
    Point,
    TlsMode,
    Value,
    ValueKind,
)
from custom_components.plc_bridge.plc.vendors import client_class
from custom_components.plc_bridge.plc.vendors.s7 import CLIENT, S7Client
from custom_components.plc_bridge.plc.vendors.s7.address import AREA_DB, AREA_P, AREA_Q, variable
from custom_components.plc_bridge.plc.vendors.s7.link import Endpoint, endpoint

NORMALIZED = [
    ("db1.dbx0.0", "bool", "DB1.DBX0.0", "BOOL"),
    ("%DB1.DBB2", "BYTE", "DB1.DBB2", "BYTE"),
    ("DB1.DBW4", "INT", "DB1.DBW4", "INT"),
    ("DB 1.DBD6", "REAL", "DB1.DBD6", "REAL"),
    ("DB1.DBD6", "udint", "DB1.DBD6", "UDINT"),
    ("M10.1", "BOOL", "M10.1", "BOOL"),
    ("%MW20", "WORD", "MW20", "WORD"),
    ("MB0", "CHAR", "MB0", "CHAR"),
    ("MD4", "DINT", "MD4", "DINT"),
    ("I0.0", "BOOL", "I0.0", "BOOL"),
    ("Q0.1", "BOOL", "Q0.1", "BOOL"),
    ("IW64", "UINT", "IW64", "UINT"),
    ("ib1", "BYTE", "IB1", "BYTE"),
    ("ID4", "DWORD", "ID4", "DWORD"),
    ("QB0", "BYTE", "QB0", "BYTE"),
    ("QW2", "INT", "QW2", "INT"),
    ("QD4", "REAL", "QD4", "REAL"),
    ("T5", "WORD", "T5", "WORD"),
    ("C3", "WORD", "C3", "WORD"),
    ("Z3", "word", "C3", "WORD"),
    ("V10.3", "BOOL", "V10.3", "BOOL"),
    ("VB100", "BYTE", "VB100", "BYTE"),
    ("VW100", "INT", "VW100", "INT"),
    ("VD100", "REAL", "VD100", "REAL"),
    ("E0.0", "BOOL", "I0.0", "BOOL"),
    ("A0.1", "BOOL", "Q0.1", "BOOL"),
    ("EW2", "INT", "IW2", "INT"),
    ("AB3", "BYTE", "QB3", "BYTE"),
    ("PIW256", "INT", "PIW256", "INT"),
    ("PEW256", "INT", "PIW256", "INT"),
    ("PQW256", "WORD", "PQW256", "WORD"),
    ("PAD256", "DWORD", "PQD256", "DWORD"),
    ("DB1.DBB10", "STRING[20]", "DB1.DBB10", "STRING[20]"),
    ("DB1.DBB10", "string [254]", "DB1.DBB10", "STRING"),
    ("DB1.DBB10", "STRING", "DB1.DBB10", "STRING"),
    ("DB1.DBB0", "LREAL", "DB1.DBB0", "LREAL"),
    ("DB1.DBB0", "DT", "DB1.DBB0", "DATE_AND_TIME"),
    ("VB0", "DATE_AND_TIME", "VB0", "DATE_AND_TIME"),
    ("DB1.DBB0", "DTL", "DB1.DBB0", "DTL"),
    ("DB1.DBB0", "sint", "DB1.DBB0", "SINT"),
    ("DB1.DBB0", "LWORD", "DB1.DBB0", "LWORD"),
    ("DB1.DBD0", "TOD", "DB1.DBD0", "TIME_OF_DAY"),
    ("DB1.DBD0", "TIME", "DB1.DBD0", "TIME"),
    ("MW2", "S5TIME", "MW2", "S5TIME"),
    ("T5", "S5TIME", "T5", "S5TIME"),
    ("Z3", "COUNTER", "C3", "COUNTER"),
    ("DB1.DBW0", "DATE", "DB1.DBW0", "DATE"),
    ("DB1.DBW0", "WCHAR", "DB1.DBW0", "WCHAR"),
    ("DB1.DBB0", "WSTRING[254]", "DB1.DBB0", "WSTRING"),
    ("DB1.DBB0", "wstring[20]", "DB1.DBB0", "WSTRING[20]"),
]

REFUSED = [
    (
        "DB1.DBW4",
        "REAL",
        r"DB1.DBW4 is a word \(16 bits\) for WORD, INT, UINT, S5TIME, DATE, WCHAR or COUNTER; "
        "for REAL use DB1.DBD4",
    ),
    ("DB1.DBD4", "INT", "for INT use DB1.DBW4"),
    ("DB1.DBX0.0", "INT", "DB1.DBX0.0 is a bit for BOOL; for INT use DB1.DBW0"),
    ("MW0", "BOOL", "for BOOL use M0.0"),
    ("DB1.DBB0", "REAL", "for REAL use DB1.DBD0"),
    ("DB1.DBD0", "LREAL", "for LREAL give its first byte, e.g. DB1.DBB0"),
    ("QW0", "STRING[4]", "for STRING give its first byte, e.g. QB0"),
    ("DB1.DBX0.8", "BOOL", "bit numbers run from 0 to 7"),
    ("DB1.DBX0", "BOOL", "needs a bit number, e.g. DB1.DBX0.0"),
    ("M10", "BOOL", "needs a bit number or a width, e.g. M10.0 or MB10"),
    ("DB1.DBW4.1", "INT", "a word .* takes no bit number"),
    ("DB0.DBW0", "INT", "DB numbers run from 1 to 65535"),
    ("DB70000.DBW0", "INT", "DB numbers run from 1 to 65535"),
    ("PI0.0", "BOOL", "peripheral I/O is read by byte, word or double word"),
    ("PQ256", "WORD", r"\(PQB, PQW, PQD\), not by bit"),
    ("MW70000", "INT", "byte offsets run from 0 to 65535"),
    ("DB1.DBW65535", "INT", "runs past byte 65535"),
    ("DB1.DBB65500", "STRING", "runs past byte 65535"),
    ("T1", "INT", "T1 is a timer: read it as S5TIME or as WORD"),
    ("C1", "REAL", "C1 is a counter: read it as COUNTER or as WORD"),
    ("T1", "COUNTER", "T1 is a timer"),
    ("C1", "S5TIME", "C1 is a counter"),
    ("DB1.DBW0", "TIME", "for TIME use DB1.DBD0"),
    ("DB1.DBD0", "S5TIME", "for S5TIME use DB1.DBW0"),
    ("DB1.DBW0", "TOD", "for TIME_OF_DAY use DB1.DBD0"),
    ("DB1.DBB0", "DATE", "for DATE use DB1.DBW0"),
    ("DB1.DBW0", "SINT", "for SINT use DB1.DBB0"),
    ("DB1.DBD0", "LINT", "for LINT give its first byte, e.g. DB1.DBB0"),
    ("DB1.DBW0", "WSTRING[4]", "for WSTRING give its first byte"),
    ("DB1.DBB0", "WSTRING[0]", "a WSTRING holds 1..16382 characters, not 0"),
    ("DB1.DBB0", "WSTRING[16383]", "not 16383"),
    ("DB1.DBB40000", "WSTRING[16382]", "runs past byte 65535"),
    ("T70000", "WORD", "numbers run from 0 to 65535"),
    ("X1", "INT", "'X1' is not an S7 address; try DB1.DBX0.0"),
    ("AIW16", "INT", "not an S7 address"),
    ("DB1.DBW0", "FLOAT", "'FLOAT' is not an S7 data type"),
    ("DB1.DBB0", "STRING[0]", "a STRING holds 1..254 characters, not 0"),
    ("DB1.DBB0", "STRING[255]", "not 255"),
]


def test_client_is_registered() -> None:
    assert client_class("s7") is S7Client is CLIENT
    assert S7Client.vendor == "s7"
    assert S7Client.default_port == 102
    assert S7Client.tls_modes == (TlsMode.NONE,)
    assert S7Client.default_tls is TlsMode.NONE
    assert S7Client.needs_credentials is False
    assert S7Client.default_scan_interval == 2
    assert S7Client.data_types == (
        "BOOL", "BYTE", "CHAR", "WORD", "INT", "UINT", "DWORD", "DINT", "UDINT",
        "REAL", "LREAL", "STRING", "DATE_AND_TIME", "DTL", "SINT", "USINT", "LINT", "ULINT",
        "LWORD", "TIME", "S5TIME", "TIME_OF_DAY", "DATE", "WCHAR", "WSTRING", "COUNTER",
    )  # fmt: skip


@pytest.mark.parametrize(("address", "data_type", "normal", "normal_type"), NORMALIZED)
def test_normalized(address: str, data_type: str, normal: str, normal_type: str) -> None:
    assert S7Client.validate_point(Point(address, data_type)) == Point(normal, normal_type)


@pytest.mark.parametrize(("address", "data_type", "message"), REFUSED)
def test_refused_with_a_form_message(address: str, data_type: str, message: str) -> None:
    with pytest.raises(PlcAddressError, match=message):
        S7Client.validate_point(Point(address, data_type))


def test_areas_on_the_wire() -> None:
    v = variable(Point("VW100", "INT"))
    assert (v.area, v.db, v.start, v.size) == (AREA_DB, 1, 100, 2)
    pq = variable(Point("PQW256", "WORD"))  # read in the process image, written to P
    assert (pq.area, pq.write_area, pq.db, pq.start) == (AREA_Q, AREA_P, 0, 256)
    pi = variable(Point("PIW256", "WORD"))
    assert (pi.area, pi.write_area) == (AREA_P, 0)
    bit = variable(Point("DB3.DBX7.6", "BOOL"))
    assert (bit.db, bit.start, bit.bit, bit.size) == (3, 7, 6, 1)
    text = variable(Point("DB1.DBB10", "STRING[20]"))
    assert (text.string_length, text.size) == (20, 22)
    assert variable(Point("DB1.DBB10", "STRING")).size == 256
    assert variable(Point("T5", "WORD")).counted
    wide = variable(Point("DB1.DBB0", "WSTRING[20]"))
    assert (wide.string_length, wide.header_size, wide.size) == (20, 4, 44)
    assert variable(Point("DB1.DBB0", "WSTRING")).size == 4 + 2 * 254
    assert variable(Point("C3", "COUNTER")).counted


@pytest.mark.parametrize(
    ("data_type", "kind"),
    [
        ("BOOL", ValueKind.BOOL),
        ("udint", ValueKind.INTEGER),
        ("REAL", ValueKind.FLOAT),
        ("LREAL", ValueKind.FLOAT),
        ("CHAR", ValueKind.TEXT),
        ("STRING[20]", ValueKind.TEXT),
        ("DT", ValueKind.DATETIME),
        ("DTL", ValueKind.DATETIME),
        ("LINT", ValueKind.INTEGER),
        ("LWORD", ValueKind.INTEGER),
        ("COUNTER", ValueKind.INTEGER),
        ("TIME", ValueKind.DURATION),
        ("S5TIME", ValueKind.DURATION),
        ("TOD", ValueKind.DURATION),
        ("DATE", ValueKind.DATETIME),
        ("WCHAR", ValueKind.TEXT),
        ("WSTRING[8]", ValueKind.TEXT),
        ("nonsense", None),
    ],
)
def test_value_kind(data_type: str, kind: ValueKind | None) -> None:
    assert S7Client.value_kind(Point("DB1.DBB0", data_type)) == kind


S7_300 = {"family": "s7_300_1500"}  # the default: S7-300/400/1200/1500
S7_200 = {"family": "s7_200"}


@pytest.mark.parametrize(
    ("options", "normal"),
    [
        ({}, {"connection": "rack_slot", "rack": 0, "slot": 1} | S7_300),
        ({"rack": "0", "slot": 2.0}, {"connection": "rack_slot", "rack": 0, "slot": 2} | S7_300),
        (
            {"connection": "rack_slot", "rack": 7, "slot": 31, "model": "S7-1500"},
            {"connection": "rack_slot", "rack": 7, "slot": 31} | S7_300,
        ),
        (
            {"connection": "tsap", "local_tsap": "10.00", "remote_tsap": "10.01"} | S7_200,
            {"connection": "tsap", "local_tsap": "10.00", "remote_tsap": "10.01"} | S7_200,
        ),
        (
            {"connection": "tsap", "remote_tsap": 0x0200},
            {"connection": "tsap", "local_tsap": "01.00", "remote_tsap": "02.00"} | S7_300,
        ),
        (
            {"connection": "tsap", "local_tsap": "0x4d57", "remote_tsap": " 4d.57 "},
            {"connection": "tsap", "local_tsap": "4D.57", "remote_tsap": "4D.57"} | S7_300,
        ),
    ],
)  # fmt: skip
def test_options(options: dict[str, Any], normal: dict[str, Any]) -> None:
    assert S7Client.validate_options(options) == normal


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"rack": 8}, "rack must be a whole number from 0 to 7, not 8"),
        ({"slot": -1}, "slot must be a whole number from 0 to 31"),
        ({"slot": True}, "slot must be"),
        ({"slot": 1.5}, "slot must be"),
        ({"connection": "mpi"}, "connection must be 'rack_slot' or 'tsap', not 'mpi'"),
        ({"connection": "tsap"}, "remote_tsap is needed to connect by TSAP, e.g. 10.01"),
        ({"connection": "tsap", "remote_tsap": "1001"}, "'1001' is not a TSAP; write it as STEP 7"),
        ({"connection": "tsap", "remote_tsap": "10.001"}, "not a TSAP"),
        ({"connection": "tsap", "remote_tsap": 0x10000}, "not a TSAP"),
        ({"connection": "tsap", "remote_tsap": "10.01", "local_tsap": None}, "local_tsap None"),
        ({"family": "s7_1200"}, "family must be one of s7_300_1500, s7_200, not 's7_1200'"),
    ],
)
def test_options_refused(options: dict[str, Any], message: str) -> None:
    with pytest.raises(PlcValueError, match=message):
        S7Client.validate_options(options)
    with pytest.raises(ValueError, match=message):  # PlcValueError is a ValueError for forms
        S7Client.validate_options(options)


def test_endpoints() -> None:
    assert endpoint({"rack": 0, "slot": 2}) == Endpoint(0x0100, 0x0102)  # S7-300
    assert endpoint({}) == Endpoint(0x0100, 0x0101)  # S7-1200/1500
    assert endpoint({"rack": 1, "slot": 3}) == Endpoint(0x0100, 0x0123)
    tsap = {"connection": "tsap", "local_tsap": "10.00", "remote_tsap": "10.01"}
    assert endpoint(tsap) == Endpoint(0x1000, 0x1001)  # a CP 243-1, T and C as on an S7-300
    assert endpoint(tsap | {"family": "s7_200"}) == Endpoint(0x1000, 0x1001, s7_200=True)


@pytest.mark.parametrize(
    ("address", "data_type", "value", "checked"),
    [
        ("M0.0", "BOOL", "on", True),
        ("M0.0", "BOOL", 0, False),
        ("MB0", "BYTE", 255, 255),
        ("MW0", "INT", "-32768", -32768),
        ("MW0", "UINT", 65535.0, 65535),
        ("MD0", "DINT", -(2**31), -(2**31)),
        ("MD0", "REAL", "1.5", 1.5),
        ("MB0", "LREAL", 2, 2.0),
        ("MB0", "CHAR", "é", "é"),
        ("MB0", "STRING[3]", "abc", "abc"),
        ("MB0", "DATE_AND_TIME", "2024-01-02T03:04:05", datetime(2024, 1, 2, 3, 4, 5)),
        ("MB0", "DTL", datetime(2024, 1, 2), datetime(2024, 1, 2)),
    ],
)
def test_values_checked(address: str, data_type: str, value: Value, checked: Value) -> None:
    assert S7Client.validate_value(Point(address, data_type), value) == checked


@pytest.mark.parametrize(
    ("data_type", "value", "message"),
    [
        ("INT", 40000, "MW0 40000 is outside -32768..32767"),
        ("WORD", -1, "outside 0..65535"),
        ("INT", 1.5, "must be a whole number"),
        ("REAL", 1e39, "does not fit a REAL"),
        ("BOOL", 2, "must be true or false"),
        ("CHAR", "ab", "takes exactly one character"),
        ("STRING[3]", "abcd", "holds at most 3 characters"),
        ("STRING", "€", "Latin-1 characters only"),
        ("STRING", 5, "takes text"),
        ("DTL", "yesterday", "takes a date and time"),
        ("DATE_AND_TIME", 5, "takes a date and time"),
    ],
)
def test_values_refused(data_type: str, value: Value, message: str) -> None:
    address = (
        "MB0" if data_type in ("CHAR", "DTL", "DATE_AND_TIME") or "STRING" in data_type else "MW0"
    )
    address = "MD0" if data_type == "REAL" else "M0.0" if data_type == "BOOL" else address
    with pytest.raises(PlcValueError, match=message):
        S7Client.validate_value(Point(address, data_type), value)


def test_bad_options_fail_at_construction() -> None:
    config = ConnectionConfig(host="plc", port=102, options={"connection": "tsap"})
    with pytest.raises(PlcValueError, match="remote_tsap is needed"):
        S7Client(config)
