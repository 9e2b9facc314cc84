"""Property tests for PLCnext: whatever the input, only the project's own errors escape."""

from __future__ import annotations

import contextlib
from typing import Any

from hypothesis import given, strategies as st

from custom_components.plc_bridge.plc import PlcError, Point
from custom_components.plc_bridge.plc.vendors.plcnext import PlcnextClient, codec
from custom_components.plc_bridge.plc.vendors.plcnext.browse import declared, leaves, types
from custom_components.plc_bridge.plc.vendors.plcnext.errors import parse_error
from custom_components.plc_bridge.plc.vendors.plcnext.paths import parse_path
from custom_components.plc_bridge.plc.vendors.plcnext.placing import Reading, place

from .strategies import BOUNDED, JSON, PLCNEXT_ADDRESSES as ADDRESSES, VALUES, ZONE


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
