"""Tecomat paths, URI packing, answer walking, values and error answers, without sockets."""

from __future__ import annotations

from datetime import datetime, timedelta
import math
from typing import Any
from zoneinfo import ZoneInfo

import pytest

from custom_components.plc_bridge.plc import (
    PlcAddressError,
    PlcAuthenticationError,
    PlcProtocolError,
    PlcValueError,
    Point,
    Value,
    ValueKind,
)
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient
from custom_components.plc_bridge.plc.vendors.tecomat.arrays import answered
from custom_components.plc_bridge.plc.vendors.tecomat.browse import (
    api_object,
    listed_names,
    suggested_platform,
)
from custom_components.plc_bridge.plc.vendors.tecomat.codec import decode, dumps, guess_type
from custom_components.plc_bridge.plc.vendors.tecomat.errors import parse_error, request_error
from custom_components.plc_bridge.plc.vendors.tecomat.info import device_info, plc_status
from custom_components.plc_bridge.plc.vendors.tecomat.paths import nest, pack_names, parse_path

PRAGUE = ZoneInfo("Europe/Prague")


@pytest.mark.parametrize(
    ("text", "normal"),
    [
        ("plcType", "plcType"),
        (" myObject . favorites.sport ", "myObject.favorites.sport"),
        ("arr2[1, 3]", "arr2[1][3]"),
        ("arr3[ 01 ][2][3]", "arr3[1][2][3]"),
        ("_dum[1].valve", "_dum[1].valve"),
        ("Main.myObject3.value", "Main.myObject3.value"),
    ],
)
def test_valid_paths(text: str, normal: str) -> None:
    assert TecomatClient.validate_point(Point(text, "real")) == Point(normal, "REAL")


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "not a TecoApi variable path"),
        ("1abc", "not a TecoApi variable path"),
        ("a..b", "not a TecoApi variable path"),
        ("a[x]", "not a TecoApi variable path"),
        ("a[]", "an array index is a whole number"),
        ("a[1,]", "an array index is a whole number"),
        ("my__var", "two underscores"),
        ("a" * 65, "at most 64 characters"),
        (".".join(["abcdefghij"] * 12), "at most 128 characters"),
        ("čas", "not a TecoApi variable path"),
    ],
)
def test_invalid_paths(text: str, message: str) -> None:
    with pytest.raises(PlcAddressError, match=message):
        TecomatClient.validate_point(Point(text, "INT"))


def test_data_types() -> None:
    assert TecomatClient.validate_point(Point("a", "time_of_day")).data_type == "TOD"
    assert TecomatClient.validate_point(Point("a", "Date_And_Time")).data_type == "DT"
    with pytest.raises(PlcAddressError, match="unknown data type 'LINT'"):
        TecomatClient.validate_point(Point("a", "LINT"))
    assert TecomatClient.value_kind(Point("a", "TIME")) is ValueKind.DURATION
    assert TecomatClient.value_kind(Point("a", "DT")) is ValueKind.DATETIME
    assert TecomatClient.value_kind(Point("a", "UDINT")) is ValueKind.INTEGER
    assert TecomatClient.value_kind(Point("a", "nope")) is None
    assert len(TecomatClient.data_types) == 17


@pytest.mark.parametrize(
    ("kind", "value", "checked"),
    [
        ("BOOL", "on", True),
        ("USINT", 255.0, 255),
        ("REAL", "2.5", 2.5),
        ("LREAL", -1e250, -1e250),  # 252 plain digits: within the parser's 255
        ("TIME", 90.5, timedelta(seconds=90.5)),
        ("TIME", "1:02:03.4", timedelta(hours=1, minutes=2, seconds=3.4)),
        ("TIME", "0.0014", timedelta(milliseconds=1)),  # TIME counts whole milliseconds
        ("TIME", timedelta(days=24, seconds=73883.647), timedelta(milliseconds=2**31 - 1)),
        ("TOD", "07:30:00", timedelta(hours=7.5)),
        ("DATE", "2015-06-17", datetime(2015, 6, 17)),
        ("DT", datetime(2020, 1, 1, tzinfo=PRAGUE), datetime(2020, 1, 1, tzinfo=PRAGUE)),
        ("STRING", "", ""),
    ],
)
def test_values(kind: str, value: Value, checked: Value) -> None:
    assert TecomatClient.validate_value(Point("a", kind), value) == checked


@pytest.mark.parametrize(
    ("kind", "value", "message"),
    [
        ("SINT", 128, "outside -128..127"),
        ("REAL", 1e39, "does not fit a REAL"),
        ("LREAL", math.inf, "does not fit a LREAL"),
        ("LREAL", 1e300, "1e\\+300 written without an exponent takes 301 characters; the"),
        ("LREAL", 5e-324, "takes 326 characters; the PLC reads numbers of at most 255"),
        ("TIME", -1, "a TIME holds 0..2147483.647 s, not -1 s"),
        ("TIME", 2**31 / 1000, "a TIME holds 0..2147483.647 s, not 2147483.648 s"),
        ("TIME", math.nan, "takes a TIME in seconds or as hh:mm:ss.zzz"),
        ("TOD", "24:00:00", "a TOD holds 0..86399.999 s, not 86400 s"),
        ("TOD", "7h", "takes a TOD in seconds or as hh:mm:ss.zzz"),
        ("DATE", "17.6.2015", "takes a DATE as an ISO date"),
        ("DT", 5, "takes a DT"),
        ("DT", "1969-12-31T23:00:00", "starts on 1970-01-01"),
        ("STRING", 5, "takes text"),
        ("STRING", "x" * 256, "at most 255 characters"),
        ("STRING", '"' * 200, "with its escapes"),
        ("STRING", "°C", "ASCII text only; '°' is not ASCII"),
    ],
)
def test_values_refused(kind: str, value: Value, message: str) -> None:
    with pytest.raises(PlcValueError, match=message):
        TecomatClient.validate_value(Point("a", kind), value)


def test_paths_the_put_parser_cannot_take() -> None:
    with pytest.raises(PlcValueError, match="nests at most 32 levels"):
        TecomatClient.validate_value(Point(".".join(["a"] * 32), "INT"), 1)
    with pytest.raises(PlcValueError, match="item names of at most 64"):
        TecomatClient.validate_value(Point("a" * 60 + "[1000][1]", "INT"), 1)


def test_pack_names() -> None:
    names = [f"variable_{index:03d}" for index in range(300)] + ["x" * 100] * 3
    groups = pack_names(names)
    room = 256 - len("/TecoApi/GetObject?")
    assert all(len("&".join(group)) <= room for group in groups)
    assert sorted(name for group in groups for name in group) == sorted(names)
    assert len(groups) == math.ceil(sum(len(name) + 1 for name in names) / (room + 1))
    assert [len(group) for group in pack_names(["a"] * 300)] == [119, 119, 62]


def test_pack_names_fills_each_uri() -> None:
    names = [f"BENCH.V{index}" for index in range(1000)]  # the bench's poll
    groups = pack_names(names)
    assert sorted(name for group in groups for name in group) == sorted(names)
    assert max(len("/TecoApi/GetObject?" + "&".join(group)) for group in groups) <= 256
    # First fit decreasing needs 48; the length bound of 46 is out of reach, as 900 names
    # of 10 characters fill a URI to 21 * 11 = 231 of 238 and the shorter ones are too few.
    assert len(groups) == 47


def test_options() -> None:
    assert TecomatClient.validate_options({}) == {"auth": "digest"}
    options = {"auth": " Basic", "clock_variable": " arr2[1, 3] ", "other": 1}
    assert TecomatClient.validate_options(options) == {
        "auth": "basic",
        "clock_variable": "arr2[1][3]",
    }
    assert TecomatClient.validate_options({"clock_variable": " "}) == {"auth": "digest"}
    with pytest.raises(PlcValueError, match="authentication is Digest or Basic, not 'ntlm'"):
        TecomatClient.validate_options({"auth": "ntlm"})
    with pytest.raises(PlcValueError, match=r"^clock variable: 'set time' is not a TecoApi"):
        TecomatClient.validate_options({"clock_variable": "set time"})
    with pytest.raises(PlcValueError, match="clock variable is a variable path, not 5"):
        TecomatClient.validate_options({"clock_variable": 5})


@pytest.mark.parametrize(
    ("answer", "path", "value"),
    [
        ({"myObject": {"favorites": {"sport": "Soccer"}}}, "MyObject.Favorites.SPORT", "Soccer"),
        ({"arr2[1][3]": 1.3}, "arr2[1][3]", 1.3),
        ({"arr2[1]": [0, 1, 2, 3.5]}, "arr2[1][3]", None),  # its first index is unknown
        ({"arr2": [[0], [0, 1, 2, 4.5]]}, "arr2[1][3]", None),
        ({"_dum[1]": {"valve": 67}}, "_dum[1].valve", 67),
        ({"arr2[1][3]": {}, "arr2": [[], [0, 0, 0, 9]]}, "arr2[1][3].x", None),
    ],
)
def test_find(answer: Any, path: str, value: Any) -> None:
    found = answered(answer, [parse_path(path)])
    if value is None:
        assert found == {}
    else:
        assert found == {parse_path(path).key: value}


@pytest.mark.parametrize(
    ("answer", "path"),
    [({"a": 1}, "b"), ({"a": [1, 2]}, "a[2]"), ({"a": 1}, "a.b"), ({"a": {"b": 1}}, "a[0]")],
)
def test_find_missing(answer: Any, path: str) -> None:
    assert answered(answer, [parse_path(path)]) == {}


def test_nest() -> None:
    pairs = [
        (parse_path("myObject.first"), "Mia"),
        (parse_path("MYOBJECT.favorites.sport"), "Swimming"),
        (parse_path("arr1[5]"), "five"),
        (parse_path("_dum[1].valve"), 67),
    ]
    assert dumps(nest(pairs)) == (
        '{"myObject":{"first":"Mia","favorites":{"sport":"Swimming"}},'
        '"arr1[5]":"five","_dum[1]":{"valve":67}}'
    )
    with pytest.raises(PlcValueError, match="inside a variable written as a value"):
        nest([(parse_path("a"), 1), (parse_path("a.b"), 2)])
    with pytest.raises(PlcValueError, match="holds other variables"):
        nest([(parse_path("a.b"), 1), (parse_path("a"), 2)])


def test_dumps() -> None:
    assert dumps({"a": True, "b": 1e-05, "c": -0.0, "d": 5, "e": 'q"'}) == (
        '{"a":true,"b":0.00001,"c":0,"d":5,"e":"q\\""}'
    )


@pytest.mark.parametrize(
    ("kind", "raw", "value"),
    [
        ("BOOL", 1, True),
        ("INT", 7.0, 7),
        ("LREAL", 3, 3.0),
        ("REAL", 22.299999, 22.3),  # the PLC prints a REAL's 32 bits with six decimals
        ("REAL", 1000.000000, 1000.0),
        ("LREAL", 22.299999, 22.299999),
        ("TOD", "7:30:00", timedelta(hours=7.5)),
        ("TIME", "596:31:23.647", timedelta(milliseconds=2**31 - 1)),
        ("DATE", "2015-06-17", datetime(2015, 6, 17, tzinfo=PRAGUE)),
        ("DT", "2018-05-11T11:22:33.4Z", datetime(2018, 5, 11, 11, 22, 33, 400000, tzinfo=PRAGUE)),
        ("DT", "2018-05-11 11:22:33", datetime(2018, 5, 11, 11, 22, 33, tzinfo=PRAGUE)),
    ],
)
def test_decode(kind: str, raw: Any, value: Value) -> None:
    assert decode(kind, raw, PRAGUE, "v") == value


@pytest.mark.parametrize(
    ("kind", "raw", "message"),
    [
        ("BOOL", 2, "which is no BOOL"),
        ("USINT", 256, "which is no USINT"),
        ("INT", 1.5, "which is no INT"),
        ("REAL", "1", "which is no REAL"),
        ("DT", "2018-02-30T00:00:00.000Z", "which is no DT"),
        ("DATE", "yesterday", "which is no DATE"),
        ("TIME", "-00:00:01.000", "which is no TIME"),
        ("TIME", "596:31:23.648", "which is no TIME"),  # past chapter 4's 24d20:31:23.647
        ("TIME", "00:00:01.0005", "which is no TIME"),  # finer than a millisecond
        ("TOD", "24:00:00.000", "which is no TOD"),
        ("STRING", ["a"], "is an array"),
        ("INT", {"a": 1}, "is a structure"),
    ],
)
def test_decode_refused(kind: str, raw: Any, message: str) -> None:
    with pytest.raises(PlcProtocolError, match=message):
        decode(kind, raw, PRAGUE, "v")


@pytest.mark.parametrize(
    ("raw", "kind"),
    [
        (True, "BOOL"),
        (-5, "DINT"),
        (2**31, "UDINT"),
        (1.0, "REAL"),
        (1000.099976, "REAL"),  # 1000.1 as a REAL prints (six decimals, chapter 4)
        (12345.678711, "REAL"),
        (12345.678901, "LREAL"),  # no single prints so: an LREAL (issue 10)
        (1e300, "LREAL"),  # beyond a REAL's range
        (float("nan"), "REAL"),
        ("2018-05-11T11:22:33.456Z", "DT"),
        ("2015-06-17", "DATE"),
        ("01:02:03.450", "TIME"),
        ("hello", "STRING"),
        (None, None),
    ],
)
def test_guess_type(raw: Any, kind: str | None) -> None:
    assert guess_type(raw) == kind


def test_error_answers() -> None:
    plain = parse_error(502, b"Bad Gateway")
    assert (plain.code, plain.message) == ("502.000", "Bad Gateway")
    assert parse_error(500, b"").message == "HTTP 500"
    assert parse_error(400, b'{"error": {"code": 5}}').code == "400.000"
    teco = parse_error(
        500, b'{"error": {"code": "500.010", "message": "Public file \'x\' is not found"}}'
    )
    assert "build the program in Mosaic" in str(request_error(teco, "digest"))
    assert "publishes no variables" in str(
        request_error(parse_error(400, b'{"error": {"code": "400.006"}}'), "digest")
    )
    other = request_error(parse_error(401, b"", 'Digest realm="x"'), "digest")
    assert isinstance(other, PlcAuthenticationError)
    assert "did not accept the credentials" in str(other)
    unknown = request_error(
        parse_error(400, b'{"error": {"code": "400.016", "message": "m"}}'), "basic"
    )
    assert isinstance(unknown, PlcProtocolError)
    assert str(unknown).endswith("m (400.016)")


def test_info_answers() -> None:
    with pytest.raises(PlcProtocolError, match="no plc block"):
        device_info({"api": {}})
    minimal = {"plc": {"mode": "STOP", "time": "not a time", "userProg": None}}
    assert device_info(minimal).model == "Tecomat"
    status = plc_status(minimal, PRAGUE)
    assert (status.mode, status.clock, status.extra) == ("STOP", None, {})


def test_listing_and_objects() -> None:
    listing = [{"plcName": {}}, {"Main": {"pump": {}, "level": {}}}, 5]
    assert listed_names(listing) == ["plcName", "Main.pump", "Main.level"]
    assert listed_names("nonsense") == []
    item = api_object(
        parse_path("Main.x"), {"value": 1.5, "attr": {"minValue": "0", "maxValue": 9}}
    )
    assert item is not None
    assert (item.address, item.minimum, item.maximum, item.name, item.platform) == (
        "Main.x.value",
        None,
        None,
        None,
        "number",
    )
    assert api_object(parse_path("a"), {"value": None, "attr": {}}) is None
    assert api_object(parse_path("a"), {"value": 1}) is None
    assert suggested_platform("STRING", False) == "text"
    assert suggested_platform("DT", True) == "sensor"
    assert suggested_platform("DATE", False) == "datetime"
