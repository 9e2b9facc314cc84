"""What a point covers in each vendor's PLC, and which addresses no write can ever reach."""

from __future__ import annotations

import pytest

from custom_components.plc_bridge.plc import (
    ConnectionConfig,
    Footprint,
    PlcAddressError,
    PlcValueError,
    Point,
)
from custom_components.plc_bridge.plc.vendors import client_class
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from simulators.s7_smart import S7SmartSimulator
from simulators.s7_smart.server import STRINGS

pytestmark = pytest.mark.no_pacing


def overlap(vendor: str, first: tuple[str, str], second: tuple[str, str]) -> bool:
    """True when the two (validated) points of the vendor cover some of the same data."""
    client = client_class(vendor)
    one = client.footprint(client.validate_point(Point(*first)))
    other = client.footprint(client.validate_point(Point(*second)))
    assert one.overlaps(other) == other.overlaps(one)
    return one.overlaps(other)


@pytest.mark.parametrize(
    ("vendor", "first", "second"),
    [
        ("s7_smart", ("VW100", "signed"), ("VW100", "unsigned")),
        ("s7_smart", ("VW100", "signed"), ("VB100", "unsigned")),
        ("s7_smart", ("VW100", "signed"), ("vb101", "raw")),
        ("s7_smart", ("VD100", "float"), ("V103.7", "signed")),
        ("s7_smart", ("VB100", "string"), ("VW200", "signed")),  # never read: all it may hold
        ("s7_smart", ("VB500", "string[10]"), ("VB510", "unsigned")),  # its 10th character
        ("s7_smart", ("VB500", "string[10]"), ("VW509", "signed")),
        ("s7_smart", ("VB500", "String [ 10 ]"), ("VB500", "unsigned")),  # its length byte
        ("s7", ("DB1.DBW0", "INT"), ("DB1.DBB0", "BYTE")),
        ("s7", ("DB1.DBW0", "INT"), ("DB1.DBX1.3", "BOOL")),
        ("s7", ("DB1.DBB10", "STRING[20]"), ("DB1.DBW30", "INT")),
        ("s7", ("MW4", "INT"), ("M5.0", "BOOL")),
        ("s7", ("QW0", "WORD"), ("PQW0", "WORD")),  # a PQ write updates the process image
        ("softplc", ("N7:3", "INT"), ("N7:3/4", "BOOL")),
        ("softplc", ("T4:0.DN", "BOOL"), ("T4:0/13", "BOOL")),
        ("tecomat", ("Main.Speed", "INT"), ("main.SPEED", "INT")),
        ("tecomat", ("Main.Arr", "INT"), ("main.arr[2]", "INT")),
        ("tecomat", ("Main.Arr", "INT"), ("MAIN.ARR[1, 2]", "INT")),
        ("tecomat", ("Main", "INT"), ("main.motor.speed", "REAL")),
        ("plcnext", ("Main.Recipe", "INT"), ("Arp.Plc.Eclr/main.recipe[2].weight", "INT")),
        ("plcnext", ("Main.Speed", "INT"), ("ARP.PLC.ECLR/MAIN.SPEED", "INT")),
    ],
)
def test_overlapping_points(vendor: str, first: tuple[str, str], second: tuple[str, str]) -> None:
    """Another spelling, width, type, case or an element of the same data overlaps."""
    assert overlap(vendor, first, second)


@pytest.mark.parametrize(
    ("vendor", "first", "second"),
    [
        ("s7_smart", ("VW100", "signed"), ("VB102", "unsigned")),
        ("s7_smart", ("VB500", "string[10]"), ("VB511", "unsigned")),
        ("s7_smart", ("VB500", "string[10]"), ("VW700", "signed")),  # issue 23: refused before
        ("s7_smart", ("VB500", "string[20]"), ("VD704", "signed")),
        ("s7_smart", ("VW10", "signed"), ("MW10", "signed")),
        ("s7_smart", ("AIW16", "signed"), ("AQW16", "signed")),
        ("s7_smart", ("T37", "signed"), ("C37", "signed")),
        ("s7", ("DB1.DBW0", "INT"), ("DB2.DBW0", "INT")),
        ("s7", ("DB1.DBW0", "INT"), ("DB1.DBB2", "BYTE")),
        ("s7", ("T5", "WORD"), ("T6", "WORD")),
        ("softplc", ("N7:3", "INT"), ("N7:4", "INT")),
        ("softplc", ("N7:3", "INT"), ("N9:3", "INT")),
        ("softplc", ("T4:0.PRE", "INT"), ("T4:0.ACC", "INT")),
        ("softplc", ("PD12:3000.PV", "REAL"), ("PD12:3000.SP", "REAL")),
        ("tecomat", ("Main.Speed", "INT"), ("Main.SpeedSet", "INT")),
        ("tecomat", ("Main.Arr[1]", "INT"), ("Main.Arr[2]", "INT")),
        ("plcnext", ("Main.Motor.Actual", "INT"), ("Main.Motor.Setpoint", "INT")),
    ],
)
def test_separate_points(vendor: str, first: tuple[str, str], second: tuple[str, str]) -> None:
    """Neighbouring bytes, other areas, DBs, files, members and elements do not overlap."""
    assert not overlap(vendor, first, second)


def test_softplc_tags_folded() -> None:
    """SoftPLC tag names are folded: whether the PLC folds them is open, and a guard errs safe."""
    assert overlap("softplc", ("pump", "INT"), ("Pump", "INT"))
    assert not overlap("softplc", ("pump", "INT"), ("pumps", "INT"))
    assert overlap("softplc", ("pump", "INT"), ("pump", "REAL"))


def test_path_footprints_hold_their_members() -> None:
    """A path covers what lies below it, not a name that merely starts the same."""
    arr = Footprint.of_path(["main", "arr"])
    assert arr.overlaps(Footprint.of_path(["main", "arr", 1, "x"]))
    assert not arr.overlaps(Footprint.of_path(["main", "arr2"]))
    assert Footprint.of_path(["main"]).overlaps(arr)


@pytest.mark.parametrize(
    ("vendor", "address", "data_type"),
    [
        ("s7_smart", "I0.0", "signed"),
        ("s7_smart", "IW0", "signed"),
        ("s7_smart", "AIW16", "signed"),
        ("s7_smart", "HC0", "signed"),
        ("s7_smart", "SMB28", "unsigned"),
        ("s7_smart", "SMW28", "unsigned"),  # SMB29 is read-only
        ("s7_smart", "SMB1000", "unsigned"),
        ("s7", "I0.0", "BOOL"),
        ("s7", "E0.1", "BOOL"),
        ("s7", "IW64", "INT"),
        ("s7", "PIW256", "INT"),
        ("s7", "PEW256", "INT"),
        ("softplc", "I:1", "INT"),
        ("softplc", "I1:3/2", "BOOL"),
        ("softplc", "T4:0.DN", "BOOL"),
        ("softplc", "C5:1", "INT"),
    ],
)
def test_never_writable(vendor: str, address: str, data_type: str) -> None:
    """Inputs and read-only areas are never writable, whatever the type."""
    client = client_class(vendor)
    assert not client.address_writable(client.validate_point(Point(address, data_type)))


@pytest.mark.parametrize(
    ("vendor", "address", "data_type"),
    [
        ("s7_smart", "Q0.0", "signed"),
        ("s7_smart", "VW100", "signed"),
        ("s7_smart", "AQW0", "signed"),
        ("s7_smart", "SMB30", "unsigned"),
        ("s7_smart", "T37", "signed"),
        ("s7_smart", "DATE", "raw"),
        ("s7", "Q0.1", "BOOL"),
        ("s7", "PQW256", "INT"),
        ("s7", "DB1.DBW0", "INT"),
        ("softplc", "O:0", "INT"),
        ("softplc", "N7:3/4", "BOOL"),
        ("softplc", "T4:0.PRE", "INT"),
        ("tecomat", "Main.Inputs", "INT"),
        ("plcnext", "Main.Inputs", "INT"),
    ],
)
def test_writable(vendor: str, address: str, data_type: str) -> None:
    """Outputs, memory and the vendors without an address rule stay writable."""
    client = client_class(vendor)
    assert client.address_writable(client.validate_point(Point(address, data_type)))


def test_connection_config_repr_masks_secrets() -> None:
    """Neither the password nor a client key appears in a repr (a log line, a traceback)."""
    config = ConnectionConfig(
        host="plc.local",
        port=443,
        username="hass",
        password="s3cret-pass",
        options={"client_key": "-----BEGIN PRIVATE KEY-----abc", "rack": 0, "auth": "digest"},
    )
    text = repr(config)
    assert "s3cret-pass" not in text
    assert "PRIVATE KEY" not in text
    assert "plc.local" in text
    assert "'rack': 0" in text
    assert "'auth': 'digest'" in text
    assert "password='***'" in text
    assert "password=''" in repr(ConnectionConfig(host="plc", port=80))


@pytest.mark.parametrize(
    ("vendor", "bit", "neighbour", "byte"),
    [("s7_smart", "V60.0", "V60.2", "VB60"), ("s7", "DB1.DBX60.0", "DB1.DBX60.2", "DB1.DBB60")],
)
def test_bits_beside_each_other_do_not_overlap(
    vendor: str, bit: str, neighbour: str, byte: str
) -> None:
    """A bit covers itself, not its byte: a read-only bit leaves its neighbours writable."""
    kind = "signed" if vendor == "s7_smart" else "BOOL"
    whole = "unsigned" if vendor == "s7_smart" else "BYTE"
    assert not overlap(vendor, (bit, kind), (neighbour, kind))
    assert overlap(vendor, (bit, kind), (byte, whole))


def test_declared_string_length() -> None:
    """`string[n]`: 1..254 characters, within its area; a longer value is refused unsent."""
    declared = S7SmartClient.validate_point(Point("vb500", " String[ 12 ] "))
    assert declared == Point("VB500", "string[12]")
    assert S7SmartClient.footprint(declared) == Footprint("V", 500 * 8, 513 * 8)
    assert S7SmartClient.validate_value(declared, "x" * 12) == "x" * 12
    with pytest.raises(PlcValueError, match="longer than 12"):
        S7SmartClient.validate_value(declared, "x" * 13)
    for wrong in ("string[0]", "string[255]"):
        with pytest.raises(PlcAddressError, match=r"1\.\.254 characters"):
            S7SmartClient.validate_point(Point("VB500", wrong))
    with pytest.raises(PlcAddressError, match="cannot hold a string of 20"):
        S7SmartClient.validate_point(Point("VB20470", "string[20]"))
    with pytest.raises(PlcAddressError, match="cannot hold a string"):
        S7SmartClient.validate_point(Point("VW500", "string[10]"))


def bytes_of(footprint: Footprint) -> tuple[int, int]:
    """Return the [first, end) bytes a byte-aligned footprint covers."""
    return footprint.start // 8, footprint.end // 8


@pytest.mark.parametrize("strings", STRINGS)
async def test_read_string_length(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient, strings: str
) -> None:
    """An undeclared string covers its length byte and its longest read (issue 23: a read-only
    VB500 blocked VW700 and VD704); a character beyond ASCII counts as in UTF-8; declared is
    the least."""
    s7_smart_sim.strings = strings
    text, declared = Point("VB500", "string"), Point("VB500", "string[10]")
    assert bytes_of(s7_smart_client.covers(text)) == (500, 755)  # never read: all it may hold
    s7_smart_sim.put_string("VB500", b"25\xb0C")
    await s7_smart_client.read([text])
    assert bytes_of(s7_smart_client.covers(text)) == (500, 506)  # "25°C": 5 bytes in UTF-8
    assert bytes_of(s7_smart_client.covers(declared)) == (500, 511)
    assert S7SmartClient.footprint(text) == Footprint("V", 500 * 8, 755 * 8)  # no PLC, no read
    s7_smart_sim.put_string("VB500", b"ok")
    await s7_smart_client.read([text])
    assert bytes_of(s7_smart_client.covers(text)) == (500, 506)  # the longest stays
    s7_smart_sim.put_string("VB500", b"a longer text")
    await s7_smart_client.read([declared])
    assert bytes_of(s7_smart_client.covers(declared)) == (500, 514)  # longer than declared
    assert s7_smart_client.covers(Point("VW700", "signed")) == Footprint("V", 5600, 5616)
