"""S7 fixtures, imported by the tests/plc/test_s7_*.py modules: a simulator, clients, a raw peer."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncGenerator, Awaitable, Callable, Iterable, Iterator
import struct
from typing import Any

import pytest

from custom_components.plc_bridge.plc.vendors.s7 import S7Client
from simulators.s7 import S7Simulator
from tests.loopback import ConfigFactory, config_factory, connected, running

type Answer = Callable[[bytes], bytes | None]
type Frames = Callable[[bytes], Iterable[bytes]]

DBS = {1: 512, 2: 64, 3: 300, 4: 300}

ITEM_READINGS: dict[str, dict[str, Any]] = {
    "takes_all": {},  # python-snap7's own server: whatever the PDU carries
    "refuses_8500": {"max_items": 5, "too_many": "refuse", "too_many_error": 0x8500},
    "refuses_8104": {"max_items": 5, "too_many": "refuse", "too_many_error": 0x8104},
    "answers_fewer": {"max_items": 5, "too_many": "truncate"},  # Snap7's C server, at 20
    "fails_the_rest": {"max_items": 5, "too_many": "item_codes"},
}
"""How a CPU meets a job of more items than it takes (simulators/s7/READINGS.md, row 1)."""


IDLE_READINGS: dict[str, dict[str, Any]] = {
    "closes_idle": {"idle_close": 0.2, "idle_close_how": "fin"},  # a CPU or CP: FIN when idle
    "resets_idle": {"idle_close": 0.2, "idle_close_how": "reset"},  # a firewall: RST at the next
}
"""How a CPU, CP or firewall ends an idle connection (simulators/s7/READINGS.md, row 17)."""

FRAME_READINGS: dict[str, dict[str, Any]] = {
    "one_frame": {},  # python-snap7's server: a reply in one COTP data frame
    "tpdu_128": {"frame_size": 121},  # the smallest TPDU ISO 8073 allows: 128 bytes, 7 of headers
    "frames_of_5": {"frame_size": 5},
    "frames_of_1": {"frame_size": 1},
}
"""How a CPU frames its replies (simulators/s7/READINGS.md, row 18)."""


def reading(sim: S7Simulator, switches: dict[str, Any]) -> S7Simulator:
    """Set the simulator's switches of one reading."""
    for name, value in switches.items():
        setattr(sim, name, value)
    return sim


def item_reading(sim: S7Simulator, reading: str) -> S7Simulator:
    """Make the simulator answer too many items per job as `reading` says."""
    for name, value in ITEM_READINGS[reading].items():
        setattr(sim, name, value)
    return sim


@pytest.fixture
async def s7_sim() -> AsyncGenerator[S7Simulator]:
    """An S7-300-like CPU (rack 0, slot 1, PDU 480) on a free loopback port."""
    async with running(S7Simulator(dbs=DBS)) as sim:
        yield sim


@pytest.fixture
def s7_config(s7_sim: S7Simulator) -> ConfigFactory:
    """Make the settings of a client of the simulator (Prague clock, short timeout)."""

    return config_factory(
        s7_sim,
        timeout=2.0,
        time_zone="Europe/Prague",
        options={"connection": "rack_slot", "rack": 0, "slot": 1},
    )


@pytest.fixture
async def s7_client(s7_config: ConfigFactory) -> AsyncGenerator[S7Client]:
    """A client connected to the simulator, closed afterwards."""
    async with connected(S7Client(s7_config())) as client:
        yield client


@pytest.fixture
def fast_reconnect(monkeypatch: pytest.MonkeyPatch) -> None:
    """Shorten the reconnect backoff to 50 ms doubling to 200 ms."""
    monkeypatch.setattr(S7Client, "reconnect_delay", (0.05, 0.2))


def userdata_ack(request: bytes, data: bytes, *, last: int = 0) -> bytes:
    """Answer a USERDATA request (SZL, clock) with data, as a CPU does."""
    parameters = bytes([0, 1, 0x12, 8, 0x12, 0x80 | request[15] & 0x0F, request[16], 1, 0, last])
    parameters += b"\x00\x00"
    body = bytes([0xFF, 0x09]) + len(data).to_bytes(2, "big") + data
    header = struct.pack(">BBHHHH", 0x32, 7, 0, int.from_bytes(request[4:6]), 12, len(body))
    return header + parameters + body


def setup_ack(request: bytes, pdu: int = 240) -> bytes:
    """Answer a setup communication request with a PDU size."""
    header = struct.pack(">BBHHHHBB", 0x32, 3, 0, int.from_bytes(request[4:6]), 8, 0, 0, 0)
    return header + bytes([0xF0, 0, 0, 1, 0, 1]) + pdu.to_bytes(2, "big")


def one_frame(pdu: bytes) -> Iterator[bytes]:
    """Carry an S7 PDU in one COTP data frame, marked last (EOT)."""
    yield b"\x02\xf0\x80" + pdu


class RawPeer:
    """A loopback ISO-on-TCP peer whose S7 answers a test writes (a misbehaving PLC).

    `frames` carries each answer in COTP data frames (header included), one by default.
    """

    def __init__(self, answer: Answer, frames: Frames = one_frame) -> None:
        self.answer = answer
        self.frames = frames
        self.port = 0
        self._server: asyncio.Server | None = None

    async def start(self) -> None:
        """Listen on a free loopback port."""
        self._server = await asyncio.start_server(self._serve, "127.0.0.1", 0)
        self.port = self._server.sockets[0].getsockname()[1]

    async def stop(self) -> None:
        """Stop listening and close every connection."""
        assert self._server is not None
        self._server.close()
        self._server.close_clients()
        await self._server.wait_closed()

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        """Confirm the COTP connection, then answer each S7 PDU with `answer`."""
        try:
            while True:
                head = await reader.readexactly(4)
                payload = await reader.readexactly(int.from_bytes(head[2:4]) - 4)
                if payload[1] == 0xE0:
                    replies: Iterable[bytes] = [b"\x06\xd0\x00\x01\x00\x01\x00"]
                elif payload[1] != 0xF0:  # a disconnect request
                    break
                else:
                    pdu = self.answer(payload[3:])
                    if pdu is None:
                        continue
                    replies = self.frames(pdu)
                for reply in replies:
                    writer.write(struct.pack(">BBH", 3, 0, len(reply) + 4) + reply)
                    await writer.drain()
        except (asyncio.IncompleteReadError, ConnectionError):
            pass
        writer.close()


@pytest.fixture
async def raw_peer() -> AsyncGenerator[Callable[..., Awaitable[RawPeer]]]:
    """Start raw peers answering as a test says; stopped afterwards."""
    peers: list[RawPeer] = []

    async def make(answer: Answer, frames: Frames = one_frame) -> RawPeer:
        peer = RawPeer(answer, frames)
        await peer.start()
        peers.append(peer)
        return peer

    yield make
    for peer in peers:
        await peer.stop()
