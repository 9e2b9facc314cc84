"""S7 data types beyond the classic ones: 1200/1500 integers, durations, DATE, wide text, counters.

Bytes as STEP 7 and TIA Portal define them; encoded, decoded, refused before sending, and
written to and read back from the simulator (python-snap7's server keeps the bytes as sent).
"""

from __future__ import annotations

from contextlib import suppress
from datetime import UTC, datetime, timedelta
import struct
from zoneinfo import ZoneInfo

from hypothesis import HealthCheck, given, settings, strategies as st
import pytest

from custom_components.plc_bridge.plc import (
    PlcAddressError,
    PlcError,
    PlcProtocolError,
    PlcValueError,
    Point,
    Value,
)
from custom_components.plc_bridge.plc.vendors.s7 import S7Client
from custom_components.plc_bridge.plc.vendors.s7.address import AREA_C, AREA_DB, variable
from custom_components.plc_bridge.plc.vendors.s7.codec import decode, encode, write_items
from custom_components.plc_bridge.plc.vendors.s7.planner import Span, WriteItem
from simulators.s7 import S7Simulator

from . import s7_fixtures

s7_sim = s7_fixtures.s7_sim
s7_config = s7_fixtures.s7_config
s7_client = s7_fixtures.s7_client

PRAGUE = ZoneInfo("Europe/Prague")
MS = timedelta(milliseconds=1)

TYPES: list[tuple[str, str, Value, bytes]] = [
    ("DB1.DBB0", "SINT", -128, b"\x80"),
    ("DB1.DBB1", "USINT", 255, b"\xff"),
    ("DB1.DBB2", "LINT", -2, b"\xff" * 7 + b"\xfe"),
    ("DB1.DBB10", "ULINT", 2**64 - 1, b"\xff" * 8),
    ("DB1.DBB18", "LWORD", 0x0123_4567_89AB_CDEF, bytes.fromhex("0123456789abcdef")),
    ("DB1.DBD26", "TIME", -1500 * MS, struct.pack(">i", -1500)),
    ("DB1.DBD30", "TIME", (2**31 - 1) * MS, b"\x7f\xff\xff\xff"),  # T#24D_20H_31M_23S_647MS
    ("DB1.DBD34", "TIME_OF_DAY", (86_400_000 - 1) * MS, struct.pack(">I", 86_399_999)),
    ("DB1.DBW38", "S5TIME", 12_300 * MS, b"\x11\x23"),  # 123 x 100 ms
    ("DB1.DBW40", "S5TIME", 10 * MS, b"\x00\x01"),  # 1 x 10 ms
    ("DB1.DBW42", "S5TIME", timedelta(seconds=9990), b"\x39\x99"),  # the largest: 999 x 10 s
    ("DB1.DBW44", "DATE", datetime(2024, 3, 27, tzinfo=PRAGUE), b"\x30\xd8"),  # day 12504
    ("DB1.DBW46", "DATE", datetime(1990, 1, 1, tzinfo=PRAGUE), b"\x00\x00"),
    ("DB1.DBW48", "WCHAR", "€", b"\x20\xac"),
    ("DB1.DBW50", "COUNTER", 999, b"\x09\x99"),
    ("C3", "COUNTER", 123, b"\x01\x23"),
    ("T4", "S5TIME", timedelta(seconds=2), b"\x02\x00"),  # 200 x 10 ms, the finest base
    ("DB1.DBB52", "WSTRING[4]", "hé€", b"\x00\x03\x00h\x00\xe9\x20\xac"),
    ("DB1.DBB100", "WSTRING[100]", "", b"\x00\x00"),
]


def stored(found_type: str, address: str, raw: bytes) -> bytes:
    """Return the bytes a CPU holds for a written value (a string's maximum length first)."""
    found = variable(Point(address, found_type))
    if not found.string_length:
        return raw
    return (found.string_length.to_bytes(2, "big") + raw).ljust(found.size, b"\x00")


@pytest.mark.parametrize(("address", "data_type", "value", "raw"), TYPES)
def test_encode_decode(address: str, data_type: str, value: Value, raw: bytes) -> None:
    found = variable(Point(address, data_type))
    assert encode(found, value, PRAGUE) == raw
    assert decode(found, stored(data_type, address, raw), PRAGUE) == value


@pytest.mark.parametrize(
    ("data_type", "value", "shown"),
    [
        ("S5TIME", 1.5, 1500 * MS),  # seconds, as a number entity writes them
        ("S5TIME", "1.5", 1500 * MS),
        ("TIME", 90, timedelta(seconds=90)),
        ("TIME", -0.001, -MS),
        ("TIME_OF_DAY", "3600", timedelta(hours=1)),
        ("COUNTER", "42", 42),
    ],
)
def test_durations_from_seconds(data_type: str, value: Value, shown: Value) -> None:
    width = {"TIME": "D", "TIME_OF_DAY": "D"}.get(data_type, "W")
    found = variable(Point(f"DB1.DB{width}0", data_type))
    assert decode(found, encode(found, value, PRAGUE), PRAGUE) == shown


@pytest.mark.parametrize(
    ("address", "data_type", "value", "message"),
    [
        ("DB1.DBW0", "S5TIME", timedelta(seconds=9991), r"holds 0\.\.9990 s, not 9991 s"),
        ("DB1.DBW0", "S5TIME", -MS, "not -0.001 s"),
        ("DB1.DBW0", "S5TIME", 12.345, r"steps of 0\.1 s; write 12\.3 s or 12\.4 s"),
        ("DB1.DBW0", "S5TIME", 1234, r"steps of 10 s; write 1230 s or 1240 s"),
        ("DB1.DBD0", "TIME", 2**31 * MS, "a TIME holds"),
        (
            "DB1.DBD0",
            "TIME_OF_DAY",
            timedelta(days=1),
            r"a TIME_OF_DAY holds 0\.\.86399\.999 s, not 86400 s",
        ),
        ("DB1.DBD0", "TIME", "soon", "takes a duration in seconds"),
        ("DB1.DBD0", "TIME", float("nan"), "takes a duration in seconds"),
        ("DB1.DBD0", "TIME", 1e300, "a TIME holds"),
        ("DB1.DBD0", "TIME", 10**40, "takes a duration in seconds"),
        ("DB1.DBD0", "TIME", True, "takes a duration in seconds"),
        ("C1", "COUNTER", 1000, "outside 0..999"),
        ("DB1.DBW0", "COUNTER", -1, "outside 0..999"),
        ("DB1.DBW0", "DATE", datetime(1989, 12, 31), "a DATE runs from 1990-01-01"),
        ("DB1.DBW0", "DATE", datetime(2169, 1, 1), "to 2168-12-31"),
        ("DB1.DBW0", "DATE", "tomorrow", "takes a date"),
        ("DB1.DBW0", "WCHAR", "ab", "exactly one character"),
        ("DB1.DBW0", "WCHAR", "😀", "exactly one character"),  # two UTF-16 code units
        ("DB1.DBB0", "WSTRING[2]", "abc", "at most 2 characters"),
        ("DB1.DBB0", "WSTRING[2]", "a😀", "at most 2 characters"),
        ("DB1.DBB0", "WSTRING[2]", "\ud800", "Unicode characters only"),
        ("DB1.DBB0", "SINT", 128, "outside -128..127"),
        ("DB1.DBB0", "ULINT", -1, "outside 0..18446744073709551615"),
    ],
)
def test_refused_before_sending(address: str, data_type: str, value: Value, message: str) -> None:
    with pytest.raises(PlcValueError, match=message):
        encode(variable(Point(address, data_type)), value, PRAGUE)


def test_date_refused_by_the_check() -> None:
    """validate_value refuses a DATE out of range, not only its encoding (the write action)."""
    with pytest.raises(PlcValueError, match="a DATE runs from 1990-01-01 to 2168-12-31"):
        S7Client.validate_value(Point("DB1.DBW0", "DATE"), datetime(1989, 12, 31))


@pytest.mark.parametrize(
    ("address", "data_type", "raw", "message"),
    [
        ("DB1.DBW0", "S5TIME", b"\x00\xa0", "no S5TIME"),
        ("DB1.DBW0", "COUNTER", b"\x10\x00", "no BCD count"),
        ("DB1.DBW0", "COUNTER", b"\x00\x0f", "no COUNTER"),
        ("DB1.DBD0", "TIME_OF_DAY", struct.pack(">I", 86_400_000), "past the end of a day"),
        ("DB1.DBW0", "DATE", b"\xff\xff", "after 2168-12-31"),
        ("DB1.DBW0", "WCHAR", b"\xd8\x00", "no UTF-16 text"),
        ("DB1.DBB0", "WSTRING[2]", b"\x00\x02\x00\x03abcdef", "a WSTRING of 3 characters"),
        ("DB1.DBB0", "WSTRING[2]", b"\x00\x02\x00\x01\xdc\x00", "no UTF-16 text"),
        ("DB1.DBD0", "TIME", b"\x00\x01", "too few for a TIME"),
    ],
)
def test_bad_bytes_fail_the_point(address: str, data_type: str, raw: bytes, message: str) -> None:
    with pytest.raises(PlcProtocolError, match=message):
        decode(variable(Point(address, data_type)), raw, PRAGUE)


PROPERTY = settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
NEW_TYPES = sorted({data_type: address for address, data_type, _, _ in TYPES}.items())
VALUES = (
    st.none()
    | st.booleans()
    | st.integers()
    | st.floats()
    | st.text(max_size=12)
    | st.timedeltas()
    | st.datetimes(timezones=st.just(UTC) | st.none())
)


@PROPERTY
@given(typed=st.sampled_from(NEW_TYPES), data=st.binary(max_size=40))
def test_any_bytes_decode_or_fail_the_point(typed: tuple[str, str], data: bytes) -> None:
    """Any bytes at each new type's address: a value or a PlcError, never a bare exception."""
    with suppress(PlcError):
        decode(variable(Point(typed[1], typed[0])), data, PRAGUE)


@PROPERTY
@given(typed=st.sampled_from(NEW_TYPES), value=VALUES)
def test_any_value_encodes_or_is_refused(typed: tuple[str, str], value: Value) -> None:
    """Any value for each new type: bytes that decode to the checked value, or a PlcError."""
    found = variable(Point(typed[1], typed[0]))
    try:
        raw = encode(found, value, PRAGUE)
    except PlcError:
        return
    if found.string_length:
        raw = found.string_length.to_bytes(2, "big") + raw
    back = decode(found, raw.ljust(found.size, b"\x00"), PRAGUE)
    if typed[0] != "DATE":  # a DATE keeps the day of the PLC's zone only
        assert back == S7Client.validate_value(Point(typed[1], typed[0]), value)


def test_decode_details() -> None:
    # Bits 14-15 of an S5TIME are not evaluated (STEP 7): the value stands in bits 0-13.
    assert decode(variable(Point("T1", "S5TIME")), b"\xd1\x23", PRAGUE) == 12_300 * MS
    assert decode(variable(Point("DB1.DBW0", "WCHAR")), b"\x00A", PRAGUE) == "A"
    assert decode(variable(Point("DB1.DBW0", "DATE")), b"\x30\xd8", UTC).tzinfo is UTC
    day = encode(
        variable(Point("DB1.DBW0", "DATE")), datetime(2024, 3, 26, 23, 30, tzinfo=UTC), PRAGUE
    )
    assert day == b"\x30\xd8"  # 00:30 on the 27th in the PLC's zone


def test_write_items_keep_the_declared_length() -> None:
    wide = write_items(variable(Point("DB1.DBB10", "WSTRING[20]")), "ab", PRAGUE, 480)
    assert wide == [WriteItem(Span(AREA_DB, 1, 12, 6), b"\x00\x02\x00a\x00b")]
    counter = write_items(variable(Point("Z7", "COUNTER")), 12, PRAGUE, 240)
    assert counter == [WriteItem(Span(AREA_C, 0, 7, 1), b"\x00\x12")]


async def test_round_trip(s7_sim: S7Simulator, s7_client: S7Client) -> None:
    values = {Point(address, data_type): value for address, data_type, value, _ in TYPES}
    s7_sim.set_db(1, 52, b"\x00\x04")  # the CPU declares its WSTRINGs' maximum lengths
    s7_sim.set_db(1, 100, b"\x00\x64")
    written = await s7_client.write(values)
    assert {point: result.value for point, result in written.items()} == values
    for address, data_type, _, raw in TYPES:
        found = variable(Point(address, data_type))
        want = stored(data_type, address, raw)[: len(raw) + (2 if found.string_length else 0)]
        if found.counted:
            area = "T" if data_type == "S5TIME" else "C"
            assert s7_sim.get_bytes(area, found.start, 2) == raw
        else:
            assert s7_sim.get_db(1, found.start, len(want)) == want
    result = await s7_client.read(list(values))
    assert {point: outcome.value for point, outcome in result.values.items()} == values


async def test_wstring_longer_than_the_plc_declares(
    s7_sim: S7Simulator, s7_client: S7Client
) -> None:
    s7_sim.set_db(1, 100, b"\x00\x02\x00\x00")  # a WSTRING[2] in the PLC, typed as [20]
    long, bad = (
        Point("DB1.DBB100", "WSTRING[20]"),
        Point("DB1.DBB200", "WSTRING[20]"),
    )  # zeros: no WSTRING
    written = await s7_client.write({long: "abc", bad: "x"})
    assert isinstance(written[long].error, PlcValueError)
    assert "is a WSTRING[2] in the PLC: 3 characters" in str(written[long].error)
    assert isinstance(written[bad].error, PlcAddressError)
    assert s7_sim.get_db(1, 100, 6) == b"\x00\x02\x00\x00\x00\x00"


@pytest.mark.parametrize("reading", ["bcd", "binary"])
async def test_counters_under_each_reading(
    s7_sim: S7Simulator, s7_client: S7Client, reading: str
) -> None:
    """BCD counts read as COUNTER; a binary one fails the point where it is no BCD (READINGS 15)."""
    s7_sim.counters = reading
    counts = {1: 7, 2: 123, 3: 999, 4: 300}
    for number, count in counts.items():
        s7_sim.set_counter(number, count)
    points = [Point(f"C{number}", "COUNTER") for number in counts] + [Point("C2", "WORD")]
    result = await s7_client.read(points)
    shown = {
        (point.address, point.data_type): outcome.value if outcome.ok else "failed"
        for point, outcome in result.values.items()
    }
    if reading == "bcd":
        want: dict[tuple[str, str], object] = {(f"C{n}", "COUNTER"): c for n, c in counts.items()}
        assert shown == want | {("C2", "WORD"): 0x0123}
    else:
        # 7 is the same word either way; 0x007B, 0x03E7 and 0x012C are no BCD: never shown wrong
        assert shown == {
            ("C1", "COUNTER"): 7,
            ("C2", "COUNTER"): "failed",
            ("C3", "COUNTER"): "failed",
            ("C4", "COUNTER"): "failed",
            ("C2", "WORD"): 123,
        }
