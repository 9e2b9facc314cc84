"""S7 on an imperfect wire: idle connections closed, replies in frames, a PLC gone silent.

Every test runs against each reading of its question in simulators/s7/READINGS.md (rows 17-19).
"""

from __future__ import annotations

import asyncio
from collections.abc import AsyncGenerator, Awaitable, Callable, Iterator
import logging
import time
from typing import Any

import pytest

from custom_components.plc_bridge.plc import (
    ConnectionConfig,
    PlcConnectionError,
    PlcProtocolError,
    PlcTimeoutError,
    Point,
    Value,
)
from custom_components.plc_bridge.plc.vendors.s7 import S7Client
from simulators.s7 import S7Simulator
from tests.loopback import ConfigFactory, connected, running

from . import s7_fixtures
from .s7_fixtures import (
    DBS,
    FRAME_READINGS,
    IDLE_READINGS,
    Answer,
    Frames,
    RawPeer,
    reading,
    setup_ack,
)

s7_sim = s7_fixtures.s7_sim
s7_config = s7_fixtures.s7_config
raw_peer = s7_fixtures.raw_peer

MW0 = Point("MW0", "INT")
POINTS: dict[Point, Value] = {
    Point("DB1.DBX0.1", "BOOL"): True,
    Point("DB1.DBW2", "INT"): -1234,
    Point("DB1.DBD4", "REAL"): 22.3,
    Point("DB1.DBB8", "STRING[20]"): "frames of a reply",
    Point("MW20", "WORD"): 0xBEEF,
    **{Point(f"DB3.DBW{2 * i}", "INT"): i for i in range(60)},  # a reply of ~190 bytes
}
SESSION_LOG = "custom_components.plc_bridge.plc.vendors.s7.session"
type PeerFactory = Callable[[Answer, Frames], Awaitable[RawPeer]]


@pytest.fixture(params=list(IDLE_READINGS))
async def idle_sim(request: pytest.FixtureRequest) -> AsyncGenerator[S7Simulator]:
    """A CPU that ends idle connections as the reading says."""
    async with running(reading(S7Simulator(dbs=DBS), IDLE_READINGS[request.param])) as sim:
        yield sim


@pytest.fixture(params=list(FRAME_READINGS))
async def framing_sim(request: pytest.FixtureRequest) -> AsyncGenerator[S7Simulator]:
    """A CPU that frames its replies as the reading says."""
    async with running(reading(S7Simulator(dbs=DBS), FRAME_READINGS[request.param])) as sim:
        yield sim


def config_of(sim: S7Simulator, **changes: Any) -> ConnectionConfig:
    """Return the settings of a client of `sim` (rack 0, slot 1)."""
    settings: dict[str, Any] = {"host": sim.host, "port": sim.port, "timeout": 2.0}
    return ConnectionConfig(**(settings | {"options": {"rack": 0, "slot": 1}} | changes))


def idle(sim: S7Simulator) -> float:
    """Return a wait past the simulator's idle limit."""
    assert sim.idle_close is not None
    return sim.idle_close + 0.4


async def test_reads_outlive_idle_closes(
    idle_sim: S7Simulator, caplog: pytest.LogCaptureFixture
) -> None:
    """Every poll after an idle close reads: the closed connection is renewed, quietly."""
    caplog.set_level(logging.DEBUG, SESSION_LOG)
    idle_sim.set_db(1, 4, bytes.fromhex("41b26666"))  # 22.3 as the program stores it
    async with connected(S7Client(config_of(idle_sim))) as client:
        for _ in range(3):
            await asyncio.sleep(idle(idle_sim))
            result = await client.read([MW0, Point("DB1.DBD4", "REAL")])
            assert [outcome.value for outcome in result.values.values()] == [0, 22.3]
        assert client.metrics.session_renewals >= 3
    assert not [r for r in caplog.records if r.name == SESSION_LOG and r.levelno >= logging.INFO]


async def test_a_write_is_never_sent_twice(idle_sim: S7Simulator) -> None:
    """A write on a connection known closed goes on a new one; one found closed by it fails."""
    async with connected(S7Client(config_of(idle_sim))) as client:
        await client.read([MW0])
        await asyncio.sleep(idle(idle_sim))
        written: list[bytes] = []
        idle_sim.on_request = lambda pdu: written.append(pdu) if pdu[10:11] == b"\x05" else None
        if idle_sim.idle_close_how == "reset":  # the close is only found by sending the write
            with pytest.raises(PlcConnectionError, match="a write is not sent again"):
                await client.write({MW0: 7})
            assert written == []  # the firewall reset it: it never reached the CPU
            assert (await client.read([MW0])).values[MW0].value == 0
        else:  # the CPU's FIN was in before the write: nothing sent on the closed connection
            assert (await client.write({MW0: 7}))[MW0].ok
            assert len(written) == 1
            assert (await client.read([MW0])).values[MW0].value == 7
        assert idle_sim.calls["write"] == len(written) <= 1


async def test_a_read_is_sent_once_more_only(s7_sim: S7Simulator, s7_config: ConfigFactory) -> None:
    """A read the PLC closes the connection on twice fails; it is not sent a third time."""
    async with connected(S7Client(s7_config())) as client:
        s7_sim.on_request = lambda pdu: s7_sim.drop_clients() if pdu[10:11] == b"\x04" else None
        with pytest.raises(PlcConnectionError, match="closed the connection"):
            await client.read([MW0])
        assert s7_sim.calls["read"] == 2
        s7_sim.on_request = None
        assert (await client.read([MW0])).values[MW0].ok


async def test_replies_in_frames(framing_sim: S7Simulator) -> None:
    """Connect, write, read, clock: every reply joined from its frames, whatever their size."""
    async with connected(S7Client(config_of(framing_sim))) as client:
        framing_sim.set_db(1, 8, b"\x14")  # the PLC's STRING[20] declares its maximum
        written = await client.write(POINTS)
        assert all(result.ok for result in written.values())
        result = await client.read(list(POINTS))
        assert {point: outcome.value for point, outcome in result.values.items()} == POINTS
        assert result.status.mode == "RUN"
        assert await client.read_clock()
        assert framing_sim.connections == 1


def endless(pdu: bytes) -> Iterator[bytes]:
    """Carry an answer in frames none of which is marked last (bounded, for the test's sake)."""
    for _ in range(100_000):
        yield b"\x02\xf0\x00" + pdu[:8]


async def test_a_reply_whose_frames_never_end(raw_peer: PeerFactory) -> None:
    """Frames that never end fail the request once the PDU size is passed: no hang."""

    def answer(pdu: bytes) -> bytes:
        return setup_ack(pdu, pdu=240)

    first = True

    def frames(pdu: bytes) -> Iterator[bytes]:
        nonlocal first
        if first:  # the setup's answer, in one frame
            first = False
            yield b"\x02\xf0\x80" + pdu
            return
        yield from endless(pdu)

    peer = await raw_peer(answer, frames)
    client = S7Client(ConnectionConfig(host="127.0.0.1", port=peer.port, timeout=30.0))
    try:
        with pytest.raises(PlcProtocolError, match=r"passed 240 bytes .* without the frame marked"):
            await client.connect()
    finally:
        await client.close()


@pytest.mark.parametrize(
    ("interval", "timeout", "chosen"),
    [(2.0, 10.0, 2.0), (0.2, 10.0, 1.0), (5.0, 10.0, 5.0), (30.0, 10.0, 10.0), (5.0, 2.0, 2.0)],
)
def test_request_timeout_follows_the_poll(interval: float, timeout: float, chosen: float) -> None:
    """A request waits one poll interval, at least 1 s, at most the configured timeout."""
    config = ConnectionConfig(host="127.0.0.1", port=102, timeout=timeout, poll_interval=interval)
    assert S7Client(config).request_timeout == chosen


async def test_a_half_open_link_is_found_by_the_next_poll(
    s7_sim: S7Simulator, s7_config: ConfigFactory, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A PLC gone silent fails the poll after one interval's wait; the next poll reconnects."""
    monkeypatch.setattr(S7Client, "shortest_timeout", 0.1)
    async with connected(S7Client(s7_config(timeout=10.0, poll_interval=0.3))) as client:
        assert client.request_timeout == 0.3
        s7_sim.silent = True
        with pytest.raises(PlcTimeoutError, match=r"did not answer within 0\.3 s"):
            await client.read([MW0])
        s7_sim.silent = False
        assert (await client.read([MW0])).values[MW0].ok
        assert s7_sim.connections == 2


async def test_a_slow_plc_is_read(s7_sim: S7Simulator, s7_config: ConfigFactory) -> None:
    """A reply later than the poll interval but within the shortest timeout counts."""
    async with connected(S7Client(s7_config(timeout=10.0, poll_interval=0.1))) as client:
        assert client.request_timeout == S7Client.shortest_timeout == 1.0
        s7_sim.on_request = lambda pdu: time.sleep(0.3)  # three intervals
        assert (await client.read([MW0])).values[MW0].ok
        assert s7_sim.connections == 1
