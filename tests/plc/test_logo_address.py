"""LOGO! addresses as LOGO!Soft Comfort names them: parsed, checked, mapped per generation."""

from __future__ import annotations

import pytest

from custom_components.plc_bridge.plc import PlcAddressError, PlcOptionError, Point
from custom_components.plc_bridge.plc.vendors import client_class
from custom_components.plc_bridge.plc.vendors.logo import LogoClient
from custom_components.plc_bridge.plc.vendors.logo.address import variable


@pytest.mark.parametrize(
    ("address", "data_type", "generation", "start", "bit"),
    [
        ("I1", "BOOL", "0ba7", 923, 0),
        ("I9", "BOOL", "0ba7", 924, 0),
        ("AI1", "INT", "0ba7", 926, None),
        ("Q16", "BOOL", "0ba7", 943, 7),
        ("AQ2", "INT", "0ba7", 946, None),
        ("M27", "BOOL", "0ba7", 951, 2),
        ("AM16", "INT", "0ba7", 982, None),
        ("I1", "BOOL", "0ba8", 1024, 0),
        ("AI8", "INT", "0ba8", 1046, None),
        ("Q20", "BOOL", "0ba8", 1066, 3),
        ("AQ1", "INT", "0ba8", 1072, None),
        ("M64", "BOOL", "8_x", 1111, 7),
        ("AM1", "INT", "8_x", 1118, None),
        ("NI1", "BOOL", "0ba8", 1246, 0),
        ("NAI32", "INT", "0ba8", 1324, None),
        ("NQ64", "BOOL", "8_x", 1397, 7),
        ("NAQ16", "INT", "8_x", 1436, None),
        ("V10.3", "BOOL", "0ba7", 10, 3),
        ("VW848", "INT", "0ba8", 848, None),
    ],
)
def test_vm_map(address: str, data_type: str, generation: str, start: int, bit: int | None) -> None:
    """Each block lands on its generation's VM byte and bit in DB1."""
    found = variable(Point(address, data_type), generation)
    assert (found.db, found.start, found.bit) == (1, start, bit)


@pytest.mark.parametrize(
    ("typed", "normal"),
    [(" i 1 ", "I1"), ("v100", "VB100"), ("VB100", "VB100"), ("vw2", "VW2"), ("V 10.3", "V10.3")],
)
def test_written_as_logo_soft_comfort_does(typed: str, normal: str) -> None:
    """Spaces and case do not matter; a bare V address is a byte (python-snap7's Logo)."""
    data_type = "BOOL" if "." in typed or "I" in typed.upper() else "INT"
    data_type = "BYTE" if normal.startswith("VB") else data_type
    assert LogoClient.validate_point(Point(typed, data_type)).address == normal


@pytest.mark.parametrize(
    ("address", "data_type", "message"),
    [
        ("I25", "BOOL", "I1 to I24"),
        ("NAI33", "INT", "NAI1 to NAI32"),
        ("I0", "BOOL", "I1 to I24"),
        ("AI1", "BOOL", "INT or WORD"),
        ("Q1", "INT", "read it as BOOL"),
        ("V850", "BYTE", "past V849"),
        ("VD848", "DINT", "past V849"),
        ("V10.8", "BOOL", "bit numbers"),
        ("VW10.1", "INT", "no bit"),
        ("DB1.DBW0", "INT", "not a LOGO! address"),
        ("VW0", "STRING", "no STRING"),
    ],
)
def test_refused_with_a_hint(address: str, data_type: str, message: str) -> None:
    """An address no generation has, or a type its block cannot hold, is refused."""
    with pytest.raises(PlcAddressError, match=message):
        LogoClient.validate_point(Point(address, data_type))


def test_footprints_in_block_terms() -> None:
    """Blocks by number, VM by bit: a VW covers its bytes' bits, not a block's image."""
    assert LogoClient.footprint(Point("AI2", "INT")) == LogoClient.footprint(Point("ai2", "WORD"))
    word, bit = (
        LogoClient.footprint(Point("VW10", "INT")),
        LogoClient.footprint(Point("V11.0", "BOOL")),
    )
    assert word.area == bit.area == "logo:V"
    assert word.start <= bit.start < word.end
    assert LogoClient.footprint(Point("I1", "BOOL")).area == "logo:I"


def test_writable_only_vm_and_network_inputs() -> None:
    """V, NI and NAI take writes; inputs, outputs, flags and network outputs do not."""
    writable = {
        address
        for address, data_type in [
            *(("V0.0", "BOOL"), ("VW0", "INT"), ("NI1", "BOOL"), ("NAI1", "INT")),
            *(("I1", "BOOL"), ("Q1", "BOOL"), ("M1", "BOOL"), ("AI1", "INT"), ("AQ1", "INT")),
            *(("AM1", "INT"), ("NQ1", "BOOL"), ("NAQ1", "INT")),
        ]
        if LogoClient.address_writable(Point(address, data_type))
    }
    assert writable == {"V0.0", "VW0", "NI1", "NAI1"}


def test_options_default_per_generation() -> None:
    """Each generation's TSAPs are offered; a wrong generation or TSAP names its field."""
    assert LogoClient.validate_options({"generation": "0ba7"}) == {
        "generation": "0ba7",
        "local_tsap": "10.01",
        "remote_tsap": "10.00",
    }
    assert (
        LogoClient.validate_options({"generation": "8_x", "remote_tsap": "0x0200"})["remote_tsap"]
        == "02.00"
    )
    with pytest.raises(PlcOptionError) as err:
        LogoClient.validate_options({"generation": "0ba6"})
    assert err.value.option == "generation"
    with pytest.raises(PlcOptionError) as err:
        LogoClient.validate_options({"generation": "0ba8", "local_tsap": "x"})
    assert err.value.option == "local_tsap"


def test_a_configured_class_checks_its_generation() -> None:
    """Bound to a 0BA7's options, the checks refuse a network input; unbound, they take it."""
    partner = Point("NI1", "BOOL")
    assert client_class("logo").validate_point(partner) == partner
    assert client_class("logo", {"generation": "0ba8"}).validate_point(partner) == partner
    bound = client_class("logo", {"generation": "0ba7"})
    with pytest.raises(PlcAddressError, match="this LOGO! generation has none"):
        bound.validate_point(partner)
    assert bound.validate_point(Point("AM16", "INT")) == Point("AM16", "INT")
    assert issubclass(bound, LogoClient)
    assert client_class("logo", {"generation": "9"}) is LogoClient  # its own check reports it
    assert client_class("s7", {"rack": 0, "slot": 1}) is client_class("s7")
