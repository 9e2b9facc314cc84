"""The S7 status beside the values: the CPU's operating mode and its clock; the demo's animation."""

from __future__ import annotations

from datetime import datetime, timedelta
import struct
from zoneinfo import ZoneInfo

import pytest

from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors.s7 import S7Client
from simulators.s7 import S7Simulator

from . import s7_fixtures
from .s7_fixtures import ConfigFactory

s7_sim = s7_fixtures.s7_sim
s7_config = s7_fixtures.s7_config
s7_client = s7_fixtures.s7_client

PRAGUE = ZoneInfo("Europe/Prague")
POINTS = [Point("MW0", "INT"), Point("DB1.DBD0", "REAL")]


def near(clock: datetime | None, expected: datetime) -> bool:
    """True when a status clock is within a second of a naive Prague time."""
    assert clock is not None
    assert clock.tzinfo == PRAGUE
    return abs(clock - expected.replace(tzinfo=PRAGUE)) < timedelta(seconds=1)


async def test_status_once_an_interval(
    s7_sim: S7Simulator, s7_client: S7Client, monkeypatch: pytest.MonkeyPatch
) -> None:
    """State and clock at the first poll, then kept: no poll sends a request for them until the
    interval passed (counted at the CPU); then both again, two round trips more."""
    at_first = s7_sim.clock
    result = await s7_client.read(POINTS)
    assert near(result.status.clock, at_first)
    assert s7_sim.calls["szl"] == 3  # identity (2) at connect, state at the first poll
    assert s7_client.metrics.last_poll_requests == S7Client.requests_for(POINTS) + 2
    s7_sim.clock = datetime(2024, 2, 29, 23, 59, 58)
    s7_sim.cpu_state = "STOP"
    for _ in range(3):
        before = s7_sim.requests
        result = await s7_client.read(POINTS)
        assert s7_sim.requests - before == S7Client.requests_for(POINTS) == 1
        assert near(result.status.clock, at_first)  # the last value read, not a new one
        assert result.status.mode == "RUN"
    monkeypatch.setattr(S7Client, "status_interval", 0.0)
    result = await s7_client.read(POINTS)
    assert near(result.status.clock, datetime(2024, 2, 29, 23, 59, 58))
    assert result.status.mode == "STOP"
    assert s7_client.metrics.last_poll_requests == S7Client.requests_for(POINTS) + 2
    assert (s7_sim.calls["clock"], s7_sim.calls["szl"]) == (2, 4)


async def test_set_clock_is_read_back(s7_sim: S7Simulator, s7_client: S7Client) -> None:
    await s7_client.read(POINTS)
    await s7_client.set_clock(datetime(2030, 6, 1, 8, 30, 15))
    assert near((await s7_client.read(POINTS)).status.clock, datetime(2030, 6, 1, 8, 30, 15))
    assert s7_client.metrics.last_poll_requests == S7Client.requests_for(POINTS) + 2


async def test_no_clock_function(s7_config: ConfigFactory, monkeypatch: pytest.MonkeyPatch) -> None:
    """A PLC that refuses the clock is not asked again; its polls carry no clock."""
    monkeypatch.setattr(S7Client, "status_interval", 0.0)
    sim = S7Simulator(has_clock=False)
    await sim.start()
    client = S7Client(s7_config(port=sim.port))
    try:
        await client.connect()
        for _ in range(3):
            result = await client.read(POINTS)
            assert result.status.clock is None
            assert result.status.mode == "RUN"
            assert all(outcome.ok for outcome in result.values.values())
        assert sim.calls["clock"] == 1  # the one refused at the first poll
        assert client.metrics.last_poll_requests == S7Client.requests_for(POINTS) + 1  # state
    finally:
        await client.close()
        await sim.stop()


@pytest.mark.parametrize(
    ("state", "mode"),
    [
        ("RUN", "RUN"),
        ("STOP", "STOP"),
        ("STARTUP", "STARTUP"),
        ("HOLD", "HOLD"),
        ("DEFECT", "ERROR"),
        (0x58, "RUN"),  # RUN after STARTUP, the mode before in bits 4..7
        (0x0B, None),  # link-up (H system): no mode to show, never a wrong STOP
    ],
)
async def test_cpu_states(
    s7_sim: S7Simulator, s7_client: S7Client, state: str | int, mode: str | None
) -> None:
    s7_sim.cpu_state = state
    assert (await s7_client.read([])).status.mode == mode


def test_animate() -> None:
    """DB1.DBD0 drifts like a temperature, MW20 counts; nothing else moves."""
    sim = S7Simulator(dbs={1: 64, 2: 8})
    sim.set_db(1, 4, b"\x12\x34")
    sim.set_bytes("M", 18, b"\x56\x78\x00\x07\x9a")
    before = sim.get_db(1, 0, 64), sim.get_bytes("M", 0, 256), sim.get_db(2, 0, 8)
    temperatures = []
    for second in (0, 1, 150, 450):
        sim.animate(second)
        temperatures.append(struct.unpack(">f", sim.get_db(1, 0, 4))[0])
    assert [round(value, 3) for value in temperatures] == [21.0, 21.0, 22.5, 19.5]
    assert sim.get_bytes("M", 20, 2) == (11).to_bytes(2, "big")
    after = sim.get_db(1, 0, 64), sim.get_bytes("M", 0, 256), sim.get_db(2, 0, 8)
    assert after[0][4:] == before[0][4:]
    assert after[1][:20] + after[1][22:] == before[1][:20] + before[1][22:]
    assert after[2] == before[2]
    sim.set_bytes("M", 20, (0x7FFF).to_bytes(2, "big"))
    sim.animate(451)
    assert sim.get_bytes("M", 20, 2) == b"\x80\x00"  # an INT wraps
