"""Property tests: whatever the input, only the project's own errors escape (issue 10).

Strategies and settings: tests/plc/strategies.py, shared by every property test.
"""

from __future__ import annotations

import contextlib
from datetime import datetime
from typing import Any

from hypothesis import given, strategies as st

from custom_components.plc_bridge.plc import PlcError, Point
from custom_components.plc_bridge.plc.vendors import client_class
from custom_components.plc_bridge.plc.vendors.s7 import address as s7_address, codec as s7_codec
from custom_components.plc_bridge.plc.vendors.s7_smart import codec as smart_codec
from custom_components.plc_bridge.plc.vendors.tecomat import codec as teco_codec

from .strategies import ADDRESSES, BOUNDED, JSON, VALUES, ZONE

VENDORS = ["s7_smart", "s7", "tecomat"]


@BOUNDED
@given(
    vendor=st.sampled_from(VENDORS),
    address=ADDRESSES,
    data_type=st.text(max_size=20),
    pick=st.integers(min_value=0),
)
def test_address_parsers(vendor: str, address: str, data_type: str, pick: int) -> None:
    """Any address with any type, or with one of the vendor's: a point or a PlcError."""
    client = client_class(vendor)
    for kind in (data_type, client.data_types[pick % len(client.data_types)]):
        with contextlib.suppress(PlcError):
            client.validate_point(Point(address, kind))


@BOUNDED
@given(vendor=st.sampled_from(VENDORS), value=VALUES, pick=st.integers(min_value=0))
def test_value_checks(vendor: str, value: Any, pick: int) -> None:
    """Any value for any type: the value coerced, or a PlcError; never a bare exception."""
    client = client_class(vendor)
    samples = {
        "s7_smart": ["VW0", "VD4", "V0.0", "VB8", "DATE"],
        "s7": ["DB1.DBW0", "DB1.DBD4", "M0.0", "DB1.DBB8", "DB1.DBB20"],
        "tecomat": ["plcData.varInt", "plcData.varReal", "plcData.varDT", "plcData.varString"],
    }[vendor]
    address = samples[pick % len(samples)]
    kind = client.data_types[pick % len(client.data_types)]
    try:
        point = client.validate_point(Point(address, kind))
    except PlcError:
        return
    with contextlib.suppress(PlcError):
        client.validate_value(point, value)


@BOUNDED
@given(data=st.binary(max_size=300), pick=st.integers(min_value=0))
def test_s7_decoder(data: bytes, pick: int) -> None:
    """Any bytes for any S7 type: a value or a PlcError."""
    kinds = list(client_class("s7").data_types)
    kind = kinds[pick % len(kinds)]
    client = client_class("s7")
    with contextlib.suppress(PlcError):
        point = client.validate_point(Point("DB1.DBB0", kind))
        s7_codec.decode(s7_address.variable(point), data, ZONE)


@BOUNDED
@given(raw=JSON, pick=st.integers(min_value=0))
def test_s7_smart_decoder(raw: Any, pick: int) -> None:
    """Any JSON value for any S7-200 SMART address and mode; any status block."""
    points = ["VW0", "VD4", "V0.0", "VB8", "DATE", "VB100"]
    modes = list(client_class("s7_smart").data_types)
    with contextlib.suppress(PlcError):
        node = smart_codec.node_for(Point(points[pick % len(points)], modes[pick % len(modes)]))
        smart_codec.decode(node.address, node.kind, raw, ZONE)
    with contextlib.suppress(PlcError):
        smart_codec.decode_status(raw, ZONE)


@BOUNDED
@given(raw=JSON, kind=st.sampled_from(sorted(teco_codec.KINDS)))
def test_tecomat_decoder(raw: Any, kind: str) -> None:
    """Any JSON value for any IEC type: a value or a PlcError."""
    with contextlib.suppress(PlcError):
        teco_codec.decode(kind, raw, ZONE, "x")


def test_known_datetime_still_decodes() -> None:
    """A sanity anchor for the properties above: a real DT decodes."""
    assert isinstance(teco_codec.decode("DT", "2014-05-11T18:22:33.000Z", ZONE, "x"), datetime)
