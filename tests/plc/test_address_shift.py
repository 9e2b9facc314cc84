"""Each vendor moves its own addresses for a copy of a machine (issue 26 item 3)."""

from __future__ import annotations

import pytest

from custom_components.plc_bridge.plc import PlcAddressError, Point
from custom_components.plc_bridge.plc.shifting import (
    BLOCKS,
    BYTES,
    DATA_BLOCKS,
    ELEMENTS,
    NAME,
    shifted_name,
)
from custom_components.plc_bridge.plc.vendors import client_class, implemented

MOVED = [
    ("s7", "DB10.DBW0", "INT", 24, BYTES, "", "DB10.DBW24"),
    ("s7", "DB10.DBX0.3", "BOOL", 48, BYTES, "", "DB10.DBX48.3"),
    ("s7", "MW20", "INT", 4, BYTES, "", "MW24"),
    ("s7", "Q0.1", "BOOL", 1, BYTES, "", "Q1.1"),
    ("s7", "PIW256", "INT", 2, BYTES, "", "PIW258"),
    ("s7", "VW100", "INT", 20, BYTES, "", "VW120"),
    ("s7", "DB10.DBD4", "REAL", 2, DATA_BLOCKS, "", "DB12.DBD4"),
    ("logo", "VW10", "INT", 24, BYTES, "", "VW34"),
    ("logo", "V10.3", "BOOL", 2, BYTES, "", "V12.3"),
    ("logo", "I1", "BOOL", 1, BYTES, "", "I9"),
    ("logo", "AI1", "INT", 2, BYTES, "", "AI2"),
    ("logo", "Q1", "BOOL", 4, BLOCKS, "", "Q5"),
    ("logo", "NAI1", "INT", 3, BLOCKS, "", "NAI4"),
    ("s7_smart", "VB100", "unsigned", 20, BYTES, "", "VB120"),
    ("s7_smart", "V10.3", "signed", 20, BYTES, "", "V30.3"),
    ("s7_smart", "AQW0", "signed", 4, BYTES, "", "AQW4"),
    ("s7_smart", "VB200", "string[10]", 20, BYTES, "", "VB220"),
    ("softplc", "N7:10", "INT", 5, ELEMENTS, "", "N7:15"),
    ("softplc", "B3/37", "BOOL", 5, ELEMENTS, "", "B3:7/5"),
    ("softplc", "T4:0.PRE", "INT", 1, ELEMENTS, "", "T4:1.PRE"),
    ("softplc", "T4:0.DN", "BOOL", 2, ELEMENTS, "", "T4:2.DN"),
    ("tecomat", "Shutter_1.Position", "INT", 1, NAME, "Shutter_1.", "Shutter_2.Position"),
    ("tecomat", "Main.shutter_1.Up", "BOOL", 11, NAME, "Shutter_1", "Main.shutter_12.Up"),
    ("tecomat", "Shutters[0].Up", "BOOL", 3, NAME, "Shutters[0].", "Shutters[3].Up"),
    ("tecomat", "Heat_07.Mode", "INT", 2, NAME, "Heat_07.", "Heat_09.Mode"),
    (
        "plcnext",
        "HomeInstance.Shutter[1].Position",
        "INT",
        1,
        NAME,
        "HomeInstance.Shutter[1].",
        "Arp.Plc.Eclr/HomeInstance.Shutter[2].Position",
    ),
    (
        "plcnext",
        "Arp.Plc.Eclr/Main.Pump_1.Speed",
        "INT",
        4,
        NAME,
        "Arp.Plc.Eclr/Main.Pump_1",
        "Arp.Plc.Eclr/Main.Pump_5.Speed",
    ),
]
REFUSED = [
    ("s7", "DB1.DBW65534", "INT", 24, BYTES, "", "byte offsets run from 0 to 65535"),
    ("s7", "T5", "S5TIME", 2, BYTES, "", "numbered, not addressed by byte"),
    ("s7", "MW20", "INT", 1, DATA_BLOCKS, "", "in no data block"),
    ("s7", "DB65535.DBW0", "INT", 1, DATA_BLOCKS, "", "DB numbers run from 1 to 65535"),
    ("s7", "MW2", "INT", -4, BYTES, "", "falls below byte 0"),
    ("logo", "V840.0", "BOOL", 24, BYTES, "", "past V849"),
    ("logo", "AI1", "INT", 1, BYTES, "", "even count"),
    ("logo", "I20", "BOOL", 8, BLOCKS, "", "I1 to I24 at most"),
    ("logo", "VW10", "INT", 1, BLOCKS, "", "moves by bytes"),
    ("s7_smart", "VD20470", "float", 20, BYTES, "", "outside V memory"),
    ("s7_smart", "DATE", "signed", 20, BYTES, "", "clock"),
    ("s7_smart", "T37", "signed", 20, BYTES, "", "numbered"),
    ("s7_smart", "AIW0", "signed", 3, BYTES, "", "even count"),
    ("s7_smart", "VB250", "string[10]", 20220, BYTES, "", "cannot hold a string"),
    ("softplc", "N7:99998", "INT", 5, ELEMENTS, "", "elements are numbered 0 to 99999"),
    ("softplc", "Motor_speed", "INT", 5, ELEMENTS, "", "tag name"),
    ("softplc", "I1", "INT", 5, ELEMENTS, "", "write its element"),
    ("tecomat", "Pump.Speed", "INT", 1, NAME, "Shutter_1.", "not in this name"),
    ("tecomat", "Shutter.Speed", "INT", 1, NAME, "Shutter.", "no number"),
    ("tecomat", "Shutter_1.Speed", "INT", 1, BYTES, "", "moves by the number"),
    ("plcnext", "Main.Shutter[1].Up", "BOOL", 1, NAME, "Other/Main.Shutter[1]", "not in Other"),
    ("plcnext", "Main.Shutter[1].Up", "BOOL", -2, NAME, "Shutter[1]", "below 0"),
]


@pytest.mark.parametrize(("vendor", "address", "data_type", "by", "unit", "part", "moved"), MOVED)
def test_address_moved(  # noqa: PLR0917 - one case per row
    vendor: str, address: str, data_type: str, by: int, unit: str, part: str, moved: str
) -> None:
    """A copy's address, as the vendor spells it, checked as the point form would."""
    client = client_class(vendor)
    point = client.validate_point(Point(address, data_type))
    shifted = client.shift_point(point, by, unit, part)
    assert shifted.address == moved
    assert client.validate_point(shifted) == shifted


@pytest.mark.parametrize(("vendor", "address", "data_type", "by", "unit", "part", "words"), REFUSED)
def test_address_refused(  # noqa: PLR0917 - one case per row
    vendor: str, address: str, data_type: str, by: int, unit: str, part: str, words: str
) -> None:
    """What cannot move so is refused with the vendor's words, never guessed."""
    client = client_class(vendor)
    point = client.validate_point(Point(address, data_type))
    with pytest.raises(PlcAddressError, match=words):
        client.shift_point(point, by, unit, part)


def test_every_vendor_moves_its_addresses() -> None:
    """Every vendor says what its stride counts, and the units are ones the model knows."""
    known = {BYTES, BLOCKS, DATA_BLOCKS, ELEMENTS, NAME}
    for vendor in implemented():
        units = client_class(vendor).shift_units
        assert units, vendor
        assert set(units) <= known, vendor


@pytest.mark.parametrize(
    ("name", "by", "moved"), [("Shutter_1", 1, "Shutter_2"), ("K09", 2, "K11"), ("X9", 1, "X10")]
)
def test_name_number_moved(name: str, by: int, moved: str) -> None:
    """The last number of a name counts; its leading zeros are kept."""
    assert shifted_name(name, by) == moved
