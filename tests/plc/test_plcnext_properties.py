"""Property tests for PLCnext: whatever the input, only the project's own errors escape."""

from __future__ import annotations

import contextlib
from datetime import UTC
from typing import Any
from zoneinfo import ZoneInfo

from hypothesis import HealthCheck, given, settings, strategies as st

from custom_components.plc_bridge.plc import PlcError, Point
from custom_components.plc_bridge.plc.vendors.plcnext import PlcnextClient, codec
from custom_components.plc_bridge.plc.vendors.plcnext.browse import declared, leaves, types
from custom_components.plc_bridge.plc.vendors.plcnext.errors import parse_error
from custom_components.plc_bridge.plc.vendors.plcnext.paths import parse_path
from custom_components.plc_bridge.plc.vendors.plcnext.placing import Reading, place

BOUNDED = settings(
    max_examples=150,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
    derandomize=True,
    database=None,
)
ZONE = ZoneInfo("Europe/Prague")
JSON = st.recursive(
    st.none()
    | st.booleans()
    | st.integers(min_value=-(10**30), max_value=10**30)
    | st.floats(allow_nan=True, allow_infinity=True)
    | st.text(max_size=30),
    lambda inner: (
        st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner, max_size=4)
    ),
    max_leaves=10,
)
VALUES = (
    st.none()
    | st.booleans()
    | st.integers()
    | st.floats()
    | st.text(max_size=40)
    | st.datetimes(timezones=st.just(UTC) | st.none())
    | st.lists(st.integers(), max_size=5)
)
ADDRESSES = st.text(max_size=40) | st.from_regex(
    r"([A-Za-z.]{0,12}/)?[A-Za-z_][A-Za-z0-9_.\[\] ;/-]{0,30}", fullmatch=True
)


@BOUNDED
@given(address=ADDRESSES, data_type=st.text(max_size=20), pick=st.integers(min_value=0))
def test_address_parser(address: str, data_type: str, pick: int) -> None:
    """Any address with any type, or one of the client's: a point or a PlcError."""
    for kind in (data_type, PlcnextClient.data_types[pick % len(PlcnextClient.data_types)]):
        with contextlib.suppress(PlcError):
            point = PlcnextClient.validate_point(Point(address, kind))
            assert PlcnextClient.validate_point(point) == point


@BOUNDED
@given(value=VALUES, kind=st.sampled_from(codec.TYPES))
def test_value_checks(value: Any, kind: str) -> None:
    """Any value for any type: coerced and encodable, or a PlcError."""
    with contextlib.suppress(PlcError):
        checked = PlcnextClient.validate_value(Point("Main.x", kind), value)
        codec.encode(kind, checked, ZONE)


@BOUNDED
@given(raw=JSON, kind=st.sampled_from(codec.TYPES))
def test_decoder(raw: Any, kind: str) -> None:
    """Any JSON value for any type: a value or a PlcError."""
    with contextlib.suppress(PlcError):
        codec.decode(kind, raw, ZONE, "x")


@BOUNDED
@given(answer=JSON, status=st.integers(min_value=100, max_value=599), raw=st.binary(max_size=60))
def test_answers(answer: Any, status: int, raw: bytes) -> None:
    """Any answer shape: placed, browsed or read as an error, or a PlcError."""
    with contextlib.suppress(PlcError):
        place(answer, [parse_path("Main.a"), parse_path("Main.b")], Reading())
    with contextlib.suppress(PlcError):
        for variable in declared({"HmiVariables2": answer}):
            list(leaves(variable, answer, types(answer)))
    assert parse_error(status, raw).status == status


NAMES = st.sampled_from(["Main.a", "Main.A", "main.a", "Main.b", "Other/Main.a", "Other/Main.B"])


@BOUNDED
@given(
    asked=st.lists(NAMES, min_size=1, max_size=5, unique_by=lambda n: parse_path(n).text),
    answered=st.lists(NAMES | st.sampled_from(["Arp.Plc.Eclr/Main.a", "Main.B"]), max_size=6),
    reverse=st.booleans(),
)
def test_no_value_under_another_path(asked: list[str], answered: list[str], reverse: bool) -> None:
    """Whatever the entries name, in whatever order: a value is placed only under a path its
    entry names (in another case only by position), never by name under another path.
    """
    paths = [parse_path(name) for name in asked]
    entries = [{"path": name, "value": name} for name in (answered[::-1] if reverse else answered)]
    reading = Reading()
    place({"variables": entries}, paths, reading)
    by_position = len(entries) == len(paths)
    for index, path in enumerate(paths):
        if path.key not in reading.found:
            continue
        value = reading.found[path.key]
        assert value.casefold() in (path.text.casefold(), path.name.casefold())
        if by_position and value == entries[index]["value"]:
            continue
        owners = [other for other in paths if value in (other.text, other.name)]
        assert not owners or path in owners
