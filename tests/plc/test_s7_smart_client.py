"""The S7-200 SMART client against the simulator: round trips, clock, limits, per-node errors."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any
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
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from simulators.s7_smart import S7SmartSimulator

pytestmark = pytest.mark.no_pacing

PRAGUE = ZoneInfo("Europe/Prague")

ROUND_TRIPS: list[tuple[str, str, Value]] = [
    ("VB10", "signed", -5),
    ("VB11", "unsigned", 250),
    ("vw20", "signed", -32768),
    ("VW22", "unsigned", 65535),
    ("VD30", "signed", -(2**31)),
    ("VD34", "unsigned", 2**32 - 1),
    ("VD40", "float", 21.3),
    ("VD44", "float", -0.0015),
    ("VB100", "string", "s7-200 smart web api."),
    ("VB400", "string", ""),
    ("VB500", "raw", [7]),
    ("VW502", "raw", [1, 2]),
    ("VD504", "raw", [1, 2, 3, 255]),
    ("IB0", "unsigned", 7),
    ("QW2", "signed", -2),
    ("MD4", "float", 2.5),
    ("MB0", "string", "abc"),
    ("SMB100", "unsigned", 9),
    ("SMD200", "signed", 5),
    ("AIW4", "signed", 1234),
    ("AQW110", "signed", -27648),
    ("T37", "signed", 100),
    ("C255", "unsigned", 65535),
    ("HC5", "signed", -1000),
    ("hc0", "raw", [0, 0, 1, 0]),
    ("T0", "raw", [1, 2]),
]


async def test_connect(s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient) -> None:
    assert s7_smart_sim.calls == {"browse": 1, "login": 1, "get_permission": 1}
    assert s7_smart_client.metrics.requests == s7_smart_sim.requests == 3


async def test_device_info(s7_smart_client: S7SmartClient) -> None:
    info = await s7_smart_client.connect()
    assert info == DeviceInfo(
        vendor="s7_smart", model="S7-200 SMART", firmware="Web API 1.0.0", can_write=True
    )


async def test_every_mode_and_area(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    values = {Point(address, mode): value for address, mode, value in ROUND_TRIPS}
    written = await s7_smart_client.write(values)
    assert {point: result.value for point, result in written.items()} == values
    assert all(result.ok for result in written.values())
    result = await s7_smart_client.read(list(values))
    assert {point: outcome.value for point, outcome in result.values.items()} == values
    assert s7_smart_sim.calls["write"] == s7_smart_sim.calls["read"] == 1
    for address, mode, value in ROUND_TRIPS:
        assert s7_smart_sim.get(address, mode) == value


async def test_big_endian_like_s7(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    s7_smart_sim.set("VW0", 0x1234, "unsigned")
    s7_smart_sim.set("VD4", 1.0, "float")
    points = [Point("VB0", "unsigned"), Point("VB1", "unsigned"), Point("VD4", "raw")]
    values = (await s7_smart_client.read(points)).values
    assert [values[p].value for p in points] == [0x12, 0x34, [0x3F, 0x80, 0, 0]]


async def test_bits(s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient) -> None:
    s7_smart_sim.set("VB10", 0b0000_0100, "unsigned")
    bits = [Point("V10.3", "signed"), Point("i31.7", "raw"), Point("Q0.0", "float")]
    bits += [Point("M5.5", "unsigned"), Point("SM100.1", "string")]
    await s7_smart_client.write(dict.fromkeys(bits, True))
    assert s7_smart_sim.get("VB10", "unsigned") == 0b0000_1100
    assert all(v.value is True for v in (await s7_smart_client.read(bits)).values.values())
    await s7_smart_client.write({Point("V10.2", "signed"): "off", Point("V10.3", "raw"): 0})
    assert s7_smart_sim.get("VB10", "unsigned") == 0
    assert (await s7_smart_client.read([bits[0]])).values[bits[0]].value is False


async def test_clock(s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient) -> None:
    s7_smart_sim.clock = datetime(2024, 2, 29, 23, 59, 58)
    assert await s7_smart_client.read_clock() == datetime(2024, 2, 29, 23, 59, 58, tzinfo=PRAGUE)
    await s7_smart_client.set_clock(datetime(2025, 1, 1, 12, 0, tzinfo=UTC))
    assert s7_smart_sim.clock == datetime(2025, 1, 1, 13, 0)  # Prague is UTC+1 in winter
    await s7_smart_client.set_clock(datetime(2030, 6, 1, 8, 30, 15))
    assert s7_smart_sim.get("DATE") == datetime(2030, 6, 1, 8, 30, 15)
    writes = s7_smart_sim.calls["write"]
    with pytest.raises(PlcValueError, match=r"2000\.\.2099"):
        await s7_smart_client.set_clock(datetime(2100, 1, 1))
    assert s7_smart_sim.calls["write"] == writes
    s7_smart_sim.mode = "STOP"
    with pytest.raises(PlcWriteRefusedError):
        await s7_smart_client.set_clock(datetime(2030, 6, 1))


async def test_clock_point_errors(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    def refuse_date(reply: dict[str, Any]) -> dict[str, Any]:
        for node in reply["result"]["data"]:
            node.update(code=3004, message="Invalid address.")
        return reply

    s7_smart_sim.rewrite = refuse_date
    with pytest.raises(PlcAddressError, match="DATE: the PLC has no such address"):
        await s7_smart_client.read_clock()
    with pytest.raises(PlcAddressError, match="DATE"):
        await s7_smart_client.set_clock(datetime(2030, 1, 1))


async def test_status(s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient) -> None:
    s7_smart_sim.clock = datetime(2024, 5, 6, 7, 8, 9)
    s7_smart_sim.mode, s7_smart_sim.forced, s7_smart_sim.system_status = "STOP", True, "Error"
    result = await s7_smart_client.read([])
    assert result.values == {}
    assert (result.status.mode, result.status.system, result.status.force) == (
        "STOP",
        "Error",
        "Forced",
    )
    assert result.status.clock == datetime(2024, 5, 6, 7, 8, 9, tzinfo=PRAGUE)
    assert s7_smart_sim.calls["read"] == 1


@pytest.mark.parametrize("count", [1, 32, 33, 100])
async def test_requests_counted(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient, count: int
) -> None:
    points = [Point(f"VW{2 * i}", "signed") for i in range(count)]
    result = await s7_smart_client.read(points)
    assert len(result.values) == count
    assert s7_smart_sim.calls["read"] == S7SmartClient.requests_for(points)
    assert s7_smart_client.metrics.last_poll_requests == S7SmartClient.requests_for(points)
    assert S7SmartClient.requests_for(points) == -(-count // 32)


async def test_one_keep_alive_connection(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    """Login, permission and three polls of four requests each travel on one TCP connection."""
    points = [Point(f"VW{2 * i}", "signed") for i in range(100)]
    for _ in range(3):
        await s7_smart_client.read(points)
    assert s7_smart_sim.requests >= 14
    assert len(s7_smart_sim.peers) == 1


async def test_duplicates_read_once(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    s7_smart_sim.set("VW0", 42)
    s7_smart_sim.set("V1.1", True)
    points = [Point("VW0", "signed"), Point("vw0", "signed"), Point(" VW0", "Signed")]
    points += [Point("V1.1", "raw"), Point("v1.1", "signed")]
    result = await s7_smart_client.read(points * 20)
    assert [result.values[p].value for p in points] == [42, 42, 42, True, True]
    assert s7_smart_sim.calls["read"] == 1


async def test_writes_packed_under_15_kb(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    text = "\x01" * 254  # each control character travels as a six-byte \u0001 escape
    values = {Point(f"VB{300 * i}", "string"): text for i in range(32)}
    written = await s7_smart_client.write(values)
    assert all(result.ok for result in written.values())
    assert s7_smart_sim.calls["write"] == 4  # about 1.5 KB a node, 9 nodes a request
    assert s7_smart_sim.get("VB9300", "string") == text
    result = await s7_smart_client.read(list(values))
    assert all(outcome.value == text for outcome in result.values.values())
    assert s7_smart_sim.calls["read"] == 1


async def test_write_nothing(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    assert await s7_smart_client.write({}) == {}
    assert s7_smart_sim.calls["write"] == 0


async def test_one_bad_address_hides_nothing(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    s7_smart_sim.v_size = 8192  # a CPU SR20: less V memory than the client's range check allows
    s7_smart_sim.set("VW0", 5)
    s7_smart_sim.set("VD4", 1.25, "float")
    good, missing, bad = Point("VW0", "signed"), Point("VW10000", "signed"), Point("VB1", "float")
    points = [good, missing, Point("VD4", "float"), bad, Point("VB99999", "signed")]
    values = (await s7_smart_client.read(points)).values
    assert (values[good].value, values[Point("VD4", "float")].value) == (5, 1.25)
    assert isinstance(values[missing].error, PlcAddressError)
    assert str(values[missing].error) == "VW10000: the PLC has no such address (code 3004)"
    assert isinstance(values[bad].error, PlcAddressError)
    assert "VB99999 is outside V memory" in str(values[Point("VB99999", "signed")].error)
    assert s7_smart_sim.calls["read"] == 1


async def test_write_node_errors(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    s7_smart_sim.v_size = 8192
    points = [Point("VW0", "signed"), Point("VW10000", "signed"), Point("SMB29", "unsigned")]
    results = await s7_smart_client.write({points[0]: 1, points[1]: 2, points[2]: 3})
    assert results[points[0]].ok
    assert results[points[0]].value == 1
    assert isinstance(results[points[1]].error, PlcAddressError)
    assert results[points[1]].value is None
    assert isinstance(results[points[2]].error, PlcWriteRefusedError)
    assert str(results[points[2]].error) == (
        "SMB29: the PLC refused it (Read-only address., code 3007)"  # its words, no guess
    )
    assert s7_smart_sim.get("VW0") == 1
    assert (await s7_smart_client.write({Point("SMB30", "unsigned"): 3}))[
        Point("SMB30", "unsigned")
    ].ok


async def test_write_checks_before_sending(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    with pytest.raises(PlcValueError):
        await s7_smart_client.write({Point("VB0", "signed"): 200})
    with pytest.raises(PlcAddressError):
        await s7_smart_client.write({Point("VB99999", "signed"): 1})
    assert s7_smart_sim.calls["write"] == 0


async def test_malformed_node_stays_in_its_point(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    def spoil(reply: dict[str, Any]) -> dict[str, Any]:
        data = reply["result"]["data"]
        data[0]["value"] = "not a number"
        data[1]["code"] = 9999
        return reply

    s7_smart_sim.rewrite = spoil
    points = [Point("VW0", "signed"), Point("VW2", "signed"), Point("VW4", "signed")]
    values = (await s7_smart_client.read(points)).values
    assert isinstance(values[points[0]].error, PlcProtocolError)
    assert isinstance(values[points[1]].error, PlcProtocolError)
    assert "code 9999" in str(values[points[1]].error)
    assert values[points[2]].value == 0
