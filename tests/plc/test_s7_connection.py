"""The S7 connection: rack/slot and TSAP, lost and restored, backoff, timeouts, odd peers."""

from __future__ import annotations

import asyncio
from collections.abc import Awaitable, Callable
import logging
import struct
import threading
import time

import pytest

from custom_components.plc_bridge.plc import (
    PlcConnectionError,
    PlcProtocolError,
    PlcSessionRefusedError,
    PlcTimeoutError,
    Point,
)
from custom_components.plc_bridge.plc.vendors.s7 import S7Client
from custom_components.plc_bridge.plc.vendors.s7.link import S7Link
from custom_components.plc_bridge.plc.vendors.s7.session import longest_wait
from simulators.s7 import S7Simulator

from . import s7_fixtures
from .s7_fixtures import Answer, ConfigFactory, RawPeer, setup_ack, userdata_ack

s7_sim = s7_fixtures.s7_sim
s7_config = s7_fixtures.s7_config
s7_client = s7_fixtures.s7_client
fast_reconnect = s7_fixtures.fast_reconnect
raw_peer = s7_fixtures.raw_peer

MW0 = Point("MW0", "INT")
LOGGER = "custom_components.plc_bridge.plc.vendors.s7.session"
type PeerFactory = Callable[[Answer], Awaitable[RawPeer]]


async def test_s7_200_by_tsap(s7_config: ConfigFactory) -> None:
    sim = S7Simulator(remote_tsap=0x1001, szl=False)  # a CP 243-1: no SZL, V memory as DB1
    await sim.start()
    options = {"connection": "tsap", "local_tsap": "10.00", "remote_tsap": "10.01"}
    client = S7Client(s7_config(port=sim.port, options=options))
    try:
        info = await client.connect()
        assert (info.model, info.serial, info.firmware) == ("SIMATIC S7", None, None)
        assert info.extra["remote_tsap"] == "10.01"
        await client.write({Point("V10.3", "BOOL"): True, Point("VW20", "INT"): -7})
        assert sim.get_bytes("V", 10, 1) == sim.get_db(1, 10, 1) == b"\x08"
        points = [Point("V10.3", "BOOL"), Point("VW20", "INT"), Point("DB1.DBW20", "INT")]
        result = await client.read(points)
        assert [result.values[p].value for p in points] == [True, -7, -7]
        assert result.status.mode is None
        assert client.metrics.last_poll_requests == 3  # the read, the state it refuses, clock
        await client.read(points)
        assert client.metrics.last_poll_requests == 1  # not asked again
    finally:
        await client.close()
        await sim.stop()


async def test_wrong_rack_or_slot_is_refused(s7_sim: S7Simulator, s7_config: ConfigFactory) -> None:
    client = S7Client(s7_config(options={"rack": 0, "slot": 2}))
    with pytest.raises(PlcSessionRefusedError, match=r"cannot connect to .* \(TSAP 01\.02\)"):
        await client.connect()
    await client.close()
    assert s7_sim.connections == 0


async def test_closed_port_is_no_refused_session(s7_config: ConfigFactory) -> None:
    """Nothing listening: a connection error, not a session the PLC refused (no slot blamed)."""
    sim = S7Simulator()
    await sim.start()
    port = sim.port
    await sim.stop()
    client = S7Client(s7_config(port=port))
    with pytest.raises(PlcConnectionError) as caught:
        await client.connect()
    await client.close()
    assert not isinstance(caught.value, PlcSessionRefusedError)


async def test_last_connection_taken(s7_config: ConfigFactory) -> None:
    sim = S7Simulator(max_clients=1)
    await sim.start()
    first, second = S7Client(s7_config(port=sim.port)), S7Client(s7_config(port=sim.port))
    try:
        await first.connect()
        with pytest.raises(PlcConnectionError):
            await second.connect()
        await first.close()
        await asyncio.sleep(0.05)
        await second.connect()
    finally:
        await first.close()
        await second.close()
        await sim.stop()


@pytest.mark.usefixtures("fast_reconnect")
async def test_restart_mid_write(
    s7_sim: S7Simulator, s7_client: S7Client, caplog: pytest.LogCaptureFixture
) -> None:
    """A write whose connection is cut before its answer fails (never sent twice); logged once."""
    caplog.set_level(logging.DEBUG, LOGGER)
    cut: list[bool] = []

    def cable_pulled_at_the_write(pdu: bytes) -> None:
        if s7_sim.calls["write"] == 1 and not cut:  # the CPU takes the write, then goes away
            cut.append(True)
            s7_sim.drop_clients()

    s7_sim.on_request = cable_pulled_at_the_write
    await s7_client.read([MW0])
    with pytest.raises(PlcConnectionError, match="not sent again"):
        await s7_client.write({MW0: 7})
    assert s7_sim.calls["write"] == 1
    assert (await s7_client.read([MW0])).values[MW0].value == 7  # reconnected at once
    assert s7_sim.connections == 2
    messages = [(r.levelno, r.getMessage()) for r in caplog.records if r.name == LOGGER]
    assert [level for level, _ in messages] == [logging.WARNING, logging.INFO]
    assert "Lost connection to S7 PLC" in messages[0][1]
    assert "restored" in messages[1][1]


@pytest.mark.usefixtures("fast_reconnect")
async def test_backoff_while_the_plc_is_away(
    s7_sim: S7Simulator,
    s7_client: S7Client,
    caplog: pytest.LogCaptureFixture,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    caplog.set_level(logging.DEBUG, LOGGER)
    attempts: list[float] = []
    real_open = S7Link.open

    async def counted_open(link: S7Link, pdu: int) -> None:
        attempts.append(time.monotonic())
        await real_open(link, pdu)

    monkeypatch.setattr(S7Link, "open", counted_open)
    await s7_sim.stop()
    with pytest.raises(PlcConnectionError, match="cannot connect"):
        await s7_client.read([MW0])  # the poll that finds it closed renews it, in vain
    assert attempts == []
    with pytest.raises(PlcConnectionError, match="cannot connect"):
        await s7_client.read([MW0])  # the next one opens a new link at once
    for _ in range(3):
        with pytest.raises(PlcConnectionError, match="next attempt in"):
            await s7_client.read([MW0])  # inside the backoff window: no attempt
    assert len(attempts) == 1
    await asyncio.sleep(0.06)
    with pytest.raises(PlcConnectionError, match="cannot connect"):
        await s7_client.read([MW0])
    with pytest.raises(PlcConnectionError, match=r"next attempt in 0\.1 s"):
        await s7_client.read([MW0])  # the window doubled
    assert len(attempts) == 2
    await s7_sim.start(s7_sim.host, s7_sim.port)
    await asyncio.sleep(0.11)
    assert (await s7_client.read([MW0])).values[MW0].ok
    assert len(attempts) == 3
    levels = [r.levelno for r in caplog.records if r.name == LOGGER]
    assert levels.count(logging.WARNING) == 1  # one line on loss, not one per poll
    assert levels.count(logging.INFO) == 1  # one line on recovery


async def test_stopped_and_restarted_mid_poll(
    s7_sim: S7Simulator, s7_config: ConfigFactory, caplog: pytest.LogCaptureFixture
) -> None:
    """The CPU reboots inside a poll; every poll then tries once, the first after it is back wins.

    Default backoff (1 s, doubling) under a 0.4 s poll interval: the wait is capped at 0.2 s.
    """
    caplog.set_level(logging.DEBUG, LOGGER)
    client = S7Client(s7_config(poll_interval=0.4))
    await client.connect()
    back: list[threading.Event] = []

    def reboot_inside_the_read(pdu: bytes) -> None:
        if s7_sim.calls["read"] == 2 and not back:
            back.append(s7_sim.reboot(downtime=0.9))

    s7_sim.on_request = reboot_inside_the_read
    try:
        assert (await client.read([MW0])).values[MW0].ok
        with pytest.raises(PlcConnectionError):
            await client.read([MW0])  # no answer leaves the CPU; the read sent again is lost
        outcomes: list[tuple[bool, str]] = []  # (the CPU was back before the poll, outcome)
        for _ in range(10):
            await asyncio.sleep(0.4)  # the poll interval
            was_back = back[0].is_set()
            try:
                await client.read([MW0])
            except PlcConnectionError as err:
                outcomes.append((was_back, str(err)))
            else:
                outcomes.append((was_back, "ok"))
                break
        assert outcomes[-1][1] == "ok"
        assert 1 <= len(outcomes) - 1 <= 4  # away ~0.9 s: the polls made meanwhile
        assert all(not was_back and "cannot connect" in text for was_back, text in outcomes[:-1])
    finally:
        await client.close()
    levels = [r.levelno for r in caplog.records if r.name == LOGGER]
    assert levels.count(logging.WARNING) == levels.count(logging.INFO) == 1


@pytest.mark.parametrize(
    ("interval", "wait"), [(10.0, 9.0), (2.0, 1.0), (1.5, 0.75), (0.4, 0.2), (600.0, 60.0)]
)
def test_longest_wait(interval: float, wait: float) -> None:
    assert longest_wait(S7Client.reconnect_delay[1], interval) == wait


async def test_backoff_capped_by_the_poll_interval(
    s7_sim: S7Simulator, s7_config: ConfigFactory
) -> None:
    """Every poll tries once; a request between polls (a write, an action) still backs off."""
    client = S7Client(s7_config(poll_interval=0.4))  # backoff 1 s, 2 s, ... capped at 0.2 s
    await client.connect()
    await s7_sim.stop()
    with pytest.raises(PlcConnectionError, match="cannot connect"):
        await client.read([MW0])  # the closed connection renewed in vain
    for _ in range(4):
        with pytest.raises(PlcConnectionError, match="cannot connect"):
            await client.read([MW0])
        with pytest.raises(PlcConnectionError, match=r"next attempt in 0\.[12] s"):
            await client.write({MW0: 1})
        await asyncio.sleep(0.2)
    await client.close()


async def test_timeout(s7_sim: S7Simulator, s7_config: ConfigFactory) -> None:
    client = S7Client(s7_config(timeout=0.1))
    await client.connect()
    s7_sim.on_request = lambda pdu: time.sleep(0.15)
    with pytest.raises(PlcTimeoutError, match=r"did not answer within 0\.1 s"):
        await client.read([MW0])
    s7_sim.on_request = None
    await asyncio.sleep(0.1)  # the late answer lands on the dropped connection
    assert (await client.read([MW0])).values[MW0].ok
    await client.close()


async def test_cancelled_poll_drops_the_session(s7_sim: S7Simulator, s7_client: S7Client) -> None:
    s7_sim.on_request = lambda pdu: time.sleep(0.1)
    poll = asyncio.create_task(s7_client.read([MW0]))
    await asyncio.sleep(0.03)
    poll.cancel()
    with pytest.raises(asyncio.CancelledError):
        await poll
    s7_sim.on_request = None
    await asyncio.sleep(0.1)
    assert (await s7_client.read([MW0])).values[MW0].ok  # a new session, no stale answer
    assert s7_sim.connections == 2


async def test_close_and_reuse(s7_sim: S7Simulator, s7_client: S7Client) -> None:
    await s7_client.close()
    await s7_client.close()
    assert (await s7_client.read([MW0])).values[MW0].ok  # reconnects on demand
    assert await s7_client.read_clock()


async def test_no_threads_left(s7_config: ConfigFactory) -> None:
    def server_threads() -> set[threading.Thread]:
        names = ("(_server_loop)", "(_handle_client)")
        return {thread for thread in threading.enumerate() if thread.name.endswith(names)}

    before = server_threads()
    sim = S7Simulator()
    await sim.start()
    client = S7Client(s7_config(port=sim.port))
    await client.connect()
    assert len(server_threads() - before) == 2  # python-snap7's listener and one client
    await sim.restart()
    assert (await client.read([MW0])).values[MW0].ok  # the connection it closed is renewed
    await client.close()
    await sim.stop()
    assert server_threads() <= before


async def test_a_peer_that_never_answers(raw_peer: PeerFactory, s7_config: ConfigFactory) -> None:
    peer = await raw_peer(lambda pdu: None)
    client = S7Client(s7_config(port=peer.port, timeout=0.1))
    with pytest.raises(PlcTimeoutError):
        await client.connect()
    await client.close()


def refuse(pdu: bytes) -> bytes:
    """Answer any job with header error 0x8104 (function not available)."""
    return struct.pack(">BBHHHHBB", 0x32, 2, 0, int.from_bytes(pdu[4:6]), 0, 0, 0x81, 4)


@pytest.mark.parametrize(
    ("answer", "error", "message"),
    [
        (lambda pdu: setup_ack(pdu, pdu=16), PlcProtocolError, "unusable PDU size 16"),
        (refuse, PlcSessionRefusedError, "refused the S7 session"),
        (lambda pdu: b"\x32\x03\x00\x00\x99\x99" + bytes(14), PlcProtocolError, "another request"),
    ],
)  # fmt: skip
async def test_odd_peers(
    raw_peer: PeerFactory,
    s7_config: ConfigFactory,
    answer: Answer,
    error: type[Exception],
    message: str,
) -> None:
    peer = await raw_peer(answer)
    client = S7Client(s7_config(port=peer.port))
    with pytest.raises(error, match=message):
        await client.connect()
    await client.close()


async def test_odd_userdata_answers(raw_peer: PeerFactory, s7_config: ConfigFactory) -> None:
    def answer(pdu: bytes) -> bytes:
        if pdu[1] == 1:
            return setup_ack(pdu)
        if pdu[15] & 0x0F == 7:  # clock: a bad BCD date
            return userdata_ack(pdu, bytes([0, 0x19, 0x24, 0x13, 1, 0, 0, 0, 0, 1]))
        return userdata_ack(pdu, b"\x04\x24\x00\x00" + bytes(4), last=1)  # endless fragments

    peer = await raw_peer(answer)
    client = S7Client(s7_config(port=peer.port))
    with pytest.raises(PlcProtocolError, match="more than 16 fragments"):
        await client.connect()
    with pytest.raises(PlcProtocolError, match="invalid BCD"):
        await client.read_clock()
    await client.close()
