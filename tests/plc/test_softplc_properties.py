"""SoftPLC property tests: whatever the input, only the project's own errors escape.

Strategies and settings: tests/plc/strategies.py, shared by every property test.
"""

from __future__ import annotations

import contextlib

from hypothesis import given, strategies as st

from custom_components.plc_bridge.plc import PlcError, Point
from custom_components.plc_bridge.plc.vendors.softplc import SoftplcClient, document
from custom_components.plc_bridge.plc.vendors.softplc.address import parse_address
from custom_components.plc_bridge.plc.vendors.softplc.codec import TYPES
from custom_components.plc_bridge.plc.vendors.softplc.planner import item_of, plan

from .strategies import BOUNDED, HEX_WORDS, SOFTPLC_ADDRESSES as ADDRESSES, SOFTPLC_REPLIES, VALUES


@BOUNDED
@given(address=ADDRESSES, data_type=st.sampled_from(["", *TYPES, "DINT"]) | st.text(max_size=6))
def test_address_parser(address: str, data_type: str) -> None:
    """The parser refuses with PlcError only; what it accepts parses again to itself."""
    try:
        point = SoftplcClient.validate_point(Point(address, data_type))
    except PlcError:
        return
    assert SoftplcClient.validate_point(point) == point
    parsed = parse_address(point.address)
    assert item_of(parsed, plan([parsed])) is not None


@BOUNDED
@given(address=ADDRESSES, data_type=st.sampled_from(TYPES), value=VALUES | HEX_WORDS)
def test_value_check(address: str, data_type: str, value: object) -> None:
    """Value checks refuse with PlcError only."""
    with contextlib.suppress(PlcError):
        SoftplcClient.validate_value(Point(address, data_type), value)  # type: ignore[arg-type]


@BOUNDED
@given(body=SOFTPLC_REPLIES)
def test_decoder(body: bytes) -> None:
    """The reply decoder refuses with PlcError only."""
    with contextlib.suppress(PlcError):
        document.parse_reply(body)


@BOUNDED
@given(
    elements=st.lists(
        st.tuples(st.sampled_from(["N7", "T4", "B3", "I1", "tag", "Tag"]), st.integers(0, 80)),
        max_size=40,
    )
)
def test_every_address_finds_its_own_item(elements: list[tuple[str, int]]) -> None:
    """Each planned address finds the one item that holds it, by bisection as by a scan."""
    addresses = [
        parse_address(name if name.lower() == "tag" else f"{name}:{element}")
        for name, element in elements
    ]
    items = plan(addresses)
    for address in addresses:
        item = item_of(address, items)
        assert item is not None
        if item.kind == "range":
            assert item.count is not None
            assert item.start <= address.element < item.start + item.count
            assert item.ad.startswith(address.text.split(":")[0] + ":")
        else:
            assert item.ad == address.ad
