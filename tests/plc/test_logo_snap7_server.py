"""python-snap7's own S7 server set up as a LOGO! (DB1 as its VM) answers the same reads."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncGenerator
import struct

import pytest
from snap7.server import Server
from snap7.type import SrvArea

from custom_components.plc_bridge.plc import ConnectionConfig, Point
from custom_components.plc_bridge.plc.vendors.logo import LogoClient
from tests.loopback import connected


@pytest.fixture
async def snap7_logo() -> AsyncGenerator[tuple[Server, bytearray, int]]:
    """python-snap7's server with a LOGO! 8's VM (1470 bytes) as DB1, on a free port."""
    server = Server(log=False)
    vm = bytearray(1470)
    server.register_area(SrvArea.DB, 1, vm)
    await asyncio.to_thread(server.start_to, "127.0.0.1", 0)
    assert server.server_socket is not None
    try:
        yield server, vm, server.server_socket.getsockname()[1]
    finally:
        await asyncio.to_thread(server.stop)


async def test_reads_and_writes_as_on_the_simulator(
    snap7_logo: tuple[Server, bytearray, int],
) -> None:
    """I3, Q1, M2, AI1, AM64, NI1 and a VW read in one request; NAI1 written lands in DB1."""
    _, vm, port = snap7_logo
    vm[1024] = 0b100  # I3
    vm[1064] = 0b1  # Q1
    vm[1104] = 0b10  # M2
    vm[1032:1034] = struct.pack(">h", 321)  # AI1
    vm[1244:1246] = struct.pack(">h", -5)  # AM64
    vm[1246] = 0b1  # NI1
    vm[100:102] = struct.pack(">h", 4711)  # VW100
    options = {"generation": "0ba8", "local_tsap": "02.00", "remote_tsap": "20.00"}
    config = ConnectionConfig(host="127.0.0.1", port=port, timeout=2.0, options=options)
    points = [
        Point("I3", "BOOL"),
        Point("Q1", "BOOL"),
        Point("M2", "BOOL"),
        Point("AI1", "INT"),
        Point("AM64", "INT"),
        Point("NI1", "BOOL"),
        Point("VW100", "INT"),
    ]
    async with connected(LogoClient(config)) as client:
        await client.read(points)
        result = await client.read(points)
        assert client.metrics.last_poll_requests == 1
        assert [result.values[point].value for point in points] == [
            True,
            True,
            True,
            321,
            -5,
            True,
            4711,
        ]
        written = await client.write({Point("NAI1", "INT"): 900})
        assert all(outcome.ok for outcome in written.values())
    assert struct.unpack(">h", vm[1262:1264])[0] == 900
