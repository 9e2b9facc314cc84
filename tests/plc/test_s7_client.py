"""The S7 client against python-snap7's server (extended in simulators/s7/): reads, writes.

python-snap7 3.3.0's own server answers every read here, with its real per-item return codes
(0x0A, 0x05). Writes, bits, clock, CPU state and SZL 0x001C/0x0424 use the simulator's
extensions, because the stock server replaces whole bytes, keeps no clock and has no state list.
"""

from __future__ import annotations

from datetime import UTC, datetime
import struct
from zoneinfo import ZoneInfo

import pytest

from custom_components.plc_bridge.plc import (
    DeviceInfo,
    PlcAddressError,
    PlcProtocolError,
    PlcValueError,
    PlcWriteRefusedError,
    Point,
    Value,
)
from custom_components.plc_bridge.plc.vendors.s7 import S7Client
from simulators.s7 import S7Simulator

from . import s7_fixtures
from .s7_fixtures import ConfigFactory

s7_sim = s7_fixtures.s7_sim
s7_config = s7_fixtures.s7_config
s7_client = s7_fixtures.s7_client

PRAGUE = ZoneInfo("Europe/Prague")

VALUES: list[tuple[str, str, Value]] = [
    ("DB1.DBX0.0", "BOOL", True),
    ("DB1.DBX0.7", "BOOL", True),
    ("DB1.DBB1", "BYTE", 200),
    ("DB1.DBB2", "CHAR", "x"),
    ("DB1.DBW4", "INT", -1234),
    ("DB1.DBW6", "WORD", 0xBEEF),
    ("DB1.DBW8", "UINT", 65000),
    ("DB1.DBD10", "REAL", 21.3),
    ("DB1.DBD14", "DINT", -70000),
    ("DB1.DBD18", "DWORD", 0xCAFEBABE),
    ("DB1.DBD22", "UDINT", 4_000_000_000),
    ("DB1.DBB26", "LREAL", 1.0e-300),
    ("DB1.DBB34", "STRING[10]", "PLC Bridge"),
    ("DB1.DBB46", "DATE_AND_TIME", datetime(2024, 2, 29, 23, 59, 58, 120000, tzinfo=PRAGUE)),
    ("DB1.DBB54", "DTL", datetime(2030, 6, 1, 8, 30, 15, 999, tzinfo=PRAGUE)),
    ("DB3.DBW298", "INT", 7),
    ("M10.1", "BOOL", True),
    ("MW20", "INT", -5),
    ("MB22", "BYTE", 9),
    ("MD24", "REAL", -0.5),
    ("Q0.1", "BOOL", True),
    ("QW2", "WORD", 513),
    ("QB4", "BYTE", 1),
    ("QD6", "DINT", 1),
    ("IB100", "BYTE", 3),
    ("IW102", "INT", 4),
    ("ID104", "DWORD", 5),
    ("I0.0", "BOOL", True),
    ("V100.3", "BOOL", True),
    ("VB101", "BYTE", 66),
    ("VW102", "INT", -66),
    ("VD104", "REAL", 6.5),
    ("T5", "WORD", 0x2123),
    ("C3", "WORD", 0x0042),
    ("PQW10", "WORD", 0x0102),
]


async def test_connect(s7_sim: S7Simulator, s7_client: S7Client) -> None:
    assert s7_sim.calls == {"setup": 1, "szl": 2}  # the status waits for the first poll
    assert s7_client.metrics.requests == s7_sim.requests == 3
    assert s7_client.pdu_size == 480
    assert s7_sim.connections == 1


async def test_device_info(s7_client: S7Client) -> None:
    assert await s7_client.connect() == DeviceInfo(
        vendor="s7",
        model="CPU 315-2 PN/DP",
        serial="S C-X4U421302009",
        firmware="V3.2.6",
        name="PLC Bridge",
        extra={
            "order_code": "6ES7 315-2EH14-0AB0",
            "module_name": "CPU 315-2 PN/DP",
            "pdu_size": "480",
            "remote_tsap": "01.01",
        },
    )


async def test_every_address_form_and_type(s7_sim: S7Simulator, s7_client: S7Client) -> None:
    values = {Point(address, data_type): value for address, data_type, value in VALUES}
    s7_sim.set_db(1, 34, b"\x0c")  # a CPU's STRING[12] declares its maximum length
    before = dict(s7_sim.calls)
    written = await s7_client.write(values)
    assert {point: result.value for point, result in written.items()} == values
    assert s7_sim.get_db(1, 34, 5) == b"\x0c\x0aPLC"  # the maximum length byte is not ours
    assert s7_sim.calls["write"] == before.get("write", 0) + 2  # 35 items: 26 fit PDU 480
    assert s7_sim.calls["read"] == before.get("read", 0) + 1  # the STRING's header, first
    result = await s7_client.read(list(values))
    assert {point: outcome.value for point, outcome in result.values.items()} == values
    # The first poll of a connection reads the CPU state and clock too.
    assert s7_client.metrics.last_poll_requests == S7Client.requests_for(list(values)) + 2
    assert s7_sim.get_db(1, 0, 2) == b"\x81\xc8"  # bits 0 and 7 of DBB0, then DBB1
    assert s7_sim.get_db(1, 4, 2) == struct.pack(">h", -1234)  # big-endian like the CPU
    assert s7_sim.get_db(1, 34, 5) == b"\x0c\x0aPLC"
    assert s7_sim.get_bytes("V", 104, 4) == s7_sim.get_db(1, 104, 4) == struct.pack(">f", 6.5)
    assert s7_sim.get_bytes("T", 5, 2) == b"\x21\x23"
    assert s7_sim.get_bytes("Q", 10, 2) == b"\x01\x02"  # PQW writes reach the outputs


async def test_known_bytes(s7_sim: S7Simulator, s7_client: S7Client) -> None:
    s7_sim.set_db(2, 0, bytes([0b0000_0100, 0x12, 0x34]) + struct.pack(">f", 1.0))
    s7_sim.set_db(2, 10, bytes([8, 3]) + b"abc")
    s7_sim.set_bytes("I", 64, b"\x80\x01")
    s7_sim.set_bytes("C", 2, b"\x09\x99")
    points = {
        Point("DB2.DBX0.2", "BOOL"): True,
        Point("DB2.DBX0.3", "BOOL"): False,
        Point("DB2.DBW1", "WORD"): 0x1234,
        Point("DB2.DBB1", "BYTE"): 0x12,
        Point("DB2.DBD3", "REAL"): 1.0,
        Point("DB2.DBB10", "STRING[8]"): "abc",
        Point("IW64", "INT"): -32767,
        Point("PIW64", "UINT"): 0x8001,
        Point("E64.7", "BOOL"): True,
        Point("C2", "WORD"): 0x0999,
    }
    result = await s7_client.read(list(points))
    assert {point: outcome.value for point, outcome in result.values.items()} == points
    assert result.status.mode == "RUN"


async def test_real_shown_as_the_float32_it_is(s7_sim: S7Simulator, s7_client: S7Client) -> None:
    """22.3 stored by the program reads 22.3, not its double expansion 22.299999237060547."""
    s7_sim.set_db(2, 20, struct.pack(">ff", 22.3, -0.1))
    s7_sim.set_bytes("M", 40, struct.pack(">f", 1e-7))
    points = [Point("DB2.DBD20", "REAL"), Point("DB2.DBD24", "REAL"), Point("MD40", "REAL")]
    result = await s7_client.read(points)
    assert [repr(result.values[point].value) for point in points] == ["22.3", "-0.1", "1e-07"]


async def test_poll_of_100_points_in_one_read(s7_sim: S7Simulator, s7_client: S7Client) -> None:
    points = [Point(f"DB3.DBW{2 * i}", "INT") for i in range(60)]
    points += [Point(f"DB4.DBD{8 * i}", "REAL") for i in range(30)]
    points += [Point(f"M{i}.{i % 8}", "BOOL") for i in range(5)]
    points += [Point(f"QB{20 * i}", "BYTE") for i in range(5)]
    result = await s7_client.read(points)
    assert all(outcome.ok for outcome in result.values.values())
    assert S7Client.requests_for(points) == 1
    for _ in range(3):  # counted at the CPU: one read a poll, the status once a minute
        before = s7_sim.requests
        result = await s7_client.read(points)
        assert s7_sim.requests - before == 1 == s7_client.metrics.last_poll_requests
        assert result.status.mode == "RUN"
        assert result.status.clock is not None


async def test_errors_per_item(s7_sim: S7Simulator, s7_client: S7Client) -> None:
    s7_sim.set_db(2, 60, b"\x00\x01\x00\x02")
    points = [
        Point("DB9.DBW0", "INT"),  # no DB9: 0x0A
        Point("DB2.DBW60", "INT"),
        Point("DB2.DBW62", "INT"),
        Point("DB2.DBW64", "INT"),  # DB2 has 64 bytes: 0x05, merged with its neighbours
        Point("nonsense", "INT"),
        Point("DB1.DBB0", "DT"),  # zeros are no DATE_AND_TIME
    ]
    before = s7_sim.calls["read"]
    first = (await s7_client.read(points)).values
    assert [first[p].value for p in points[1:3]] == [1, 2]
    assert isinstance(first[points[0]].error, PlcAddressError)
    assert "no such object" in str(first[points[0]].error)
    assert "out of range" in str(first[points[3]].error)
    assert "not an S7 address" in str(first[points[4]].error)
    assert isinstance(first[points[5]].error, PlcProtocolError)
    # The failed merged item is re-read alone, once (1 + 1). Each job ending in failed items
    # sends them again once per link (DB2 and DB9 alone: 2; DB2.DBW64 alone: 1): a CPU may fail
    # the items past its limit (simulators/s7/READINGS.md).
    assert s7_sim.calls["read"] - before == 5
    second = (await s7_client.read(points)).values
    assert {p: (r.value, str(r.error)) for p, r in second.items()} == {
        p: (r.value, str(r.error)) for p, r in first.items()
    }
    assert s7_sim.calls["read"] - before == 6  # from then on DB2.DBW64 is planned alone


async def test_writes_read_back_in_one_round_trip(s7_sim: S7Simulator, s7_client: S7Client) -> None:
    values: dict[Point, Value] = {Point(f"DB3.DBW{4 * i}", "INT"): i - 5 for i in range(15)}
    before = dict(s7_sim.calls)
    await s7_client.write(values)
    assert s7_sim.calls["write"] == before.get("write", 0) + 1
    assert s7_sim.calls["read"] == before.get("read", 0)
    read = (await s7_client.read(list(values))).values
    assert {point: outcome.value for point, outcome in read.items()} == values


async def test_bool_is_written_as_a_bit(s7_sim: S7Simulator, s7_client: S7Client) -> None:
    s7_sim.set_db(1, 0, b"\xaa")
    reads = s7_sim.calls["read"]
    await s7_client.write({Point("DB1.DBX0.0", "BOOL"): True, Point("DB1.DBX0.1", "BOOL"): 0})
    assert s7_sim.get_db(1, 0, 1) == b"\xa9"  # no read-modify-write of the byte
    assert s7_sim.calls["read"] == reads


async def test_write_errors_per_point(s7_sim: S7Simulator, s7_client: S7Client) -> None:
    values: dict[Point, Value] = {
        Point("DB9.DBW0", "INT"): 1,
        Point("DB2.DBW64", "INT"): 1,
        Point("DB2.DBW0", "INT"): 1,
        Point("DB2.DBB2", "DT"): datetime(2100, 1, 1, tzinfo=UTC),  # a year DT cannot hold
    }
    results = await s7_client.write(values)
    assert "no such object" in str(results[Point("DB9.DBW0", "INT")].error)
    assert "out of range" in str(results[Point("DB2.DBW64", "INT")].error)
    assert results[Point("DB2.DBW0", "INT")].ok
    assert isinstance(results[Point("DB2.DBB2", "DT")].error, PlcValueError)
    s7_sim.write_protected = True
    results = await s7_client.write({Point("MW0", "INT"): 1})
    assert isinstance(results[Point("MW0", "INT")].error, PlcWriteRefusedError)


async def test_bad_values_are_not_sent(s7_sim: S7Simulator, s7_client: S7Client) -> None:
    writes = s7_sim.calls["write"]
    with pytest.raises(PlcValueError, match="outside"):
        await s7_client.write({Point("MW0", "INT"): 1, Point("MW2", "INT"): 1 << 20})
    with pytest.raises(PlcAddressError):
        await s7_client.write({Point("MW0", "REAL"): 1})
    assert s7_sim.calls["write"] == writes


async def test_long_strings_on_a_small_pdu(s7_config: ConfigFactory) -> None:
    sim = S7Simulator(pdu_size=240, dbs={1: 600})
    await sim.start()
    client = S7Client(s7_config(port=sim.port))
    try:
        info = await client.connect()  # SZL 0x001C arrives in two fragments at PDU 240
        assert info.serial == "S C-X4U421302009"
        assert sim.calls["szl"] == 3
        assert client.pdu_size == 240
        text = "0123456789" * 25 + "abcd"
        points = {Point("DB1.DBB0", "STRING"): text, Point("DB1.DBB300", "STRING"): "x"}
        sim.set_db(1, 0, b"\xfe")  # the CPU declares STRING[254] and STRING[16]
        sim.set_db(1, 300, b"\x10")
        assert all(result.ok for result in (await client.write(points)).values())
        assert sim.get_db(1, 0, 3) == b"\xfe\xfe0"
        read = (await client.read(list(points))).values
        assert read[Point("DB1.DBB0", "STRING")].value == text
    finally:
        await client.close()
        await sim.stop()


async def test_clock(s7_sim: S7Simulator, s7_client: S7Client) -> None:
    s7_sim.clock = datetime(2024, 2, 29, 23, 59, 58)
    clock = await s7_client.read_clock()
    assert clock.tzinfo == PRAGUE
    assert abs((clock - datetime(2024, 2, 29, 23, 59, 58, tzinfo=PRAGUE)).total_seconds()) < 1
    await s7_client.set_clock(datetime(2025, 1, 1, 12, 0, tzinfo=UTC))
    assert abs((s7_sim.clock - datetime(2025, 1, 1, 13, 0)).total_seconds()) < 1
    await s7_client.set_clock(datetime(2030, 6, 1, 8, 30, 15))
    assert abs((s7_sim.clock - datetime(2030, 6, 1, 8, 30, 15)).total_seconds()) < 1
    clocks = s7_sim.calls["clock"]
    with pytest.raises(PlcValueError, match=r"1990\.\.2089"):
        await s7_client.set_clock(datetime(2100, 1, 1))
    assert s7_sim.calls["clock"] == clocks
    s7_sim.write_protected = True
    with pytest.raises(PlcWriteRefusedError, match="refused to set its clock"):
        await s7_client.set_clock(datetime(2030, 6, 1))


async def test_cpu_state(
    s7_sim: S7Simulator, s7_client: S7Client, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The state is read with the clock, once an interval: a change shows after it passed."""
    assert (await s7_client.read([])).status.mode == "RUN"
    s7_sim.cpu_state = "STOP"
    assert (await s7_client.read([])).status.mode == "RUN"  # kept for the interval
    monkeypatch.setattr(S7Client, "status_interval", 0.0)
    assert (await s7_client.read([])).status.mode == "STOP"
    s7_sim.cpu_state = "UNKNOWN"
    assert (await s7_client.read([])).status.mode is None


async def test_header_error_fails_the_poll(s7_sim: S7Simulator, s7_client: S7Client) -> None:
    """A refusal that no smaller job avoids says so, without PUT/GET advice: no cause here."""
    s7_sim.max_items = 0
    with pytest.raises(PlcProtocolError, match=r"refused the read: ") as caught:
        await s7_client.read([Point("MW0", "INT"), Point("DB1.DBW0", "INT")])
    assert "PUT/GET" not in str(caught.value)
    with pytest.raises(PlcWriteRefusedError):
        await s7_client.write({Point("MW0", "INT"): 1, Point("DB1.DBW0", "INT"): 1})
    s7_sim.max_items = None
    assert (await s7_client.read([Point("MW0", "INT")])).values[Point("MW0", "INT")].ok


async def test_put_get_refusal_gets_its_advice(s7_sim: S7Simulator, s7_client: S7Client) -> None:
    """Function not available (0x8104) to every job: the advice to permit PUT/GET comes along."""
    s7_sim.put_get_refused = True
    with pytest.raises(PlcProtocolError, match=r"refused the read: .* permit PUT/GET"):
        await s7_client.read([Point("MW0", "INT")])
