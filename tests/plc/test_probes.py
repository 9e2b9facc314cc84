"""Each vendor's probe says yes to its own simulator and no to every other interface."""

from __future__ import annotations

from collections.abc import AsyncGenerator
from contextlib import AsyncExitStack
import time

import aiohttp
import pytest

from custom_components.plc_bridge.plc.vendors import probe_of
from custom_components.plc_bridge.plc.vendors.s7.probe import connection_request
from simulators.plcnext import PlcnextSimulator
from simulators.s7 import S7Simulator
from simulators.s7_smart import S7SmartSimulator
from simulators.softplc import SoftplcSimulator
from simulators.tecomat import TecomatSimulator
from tests.loopback import Server, running

pytestmark = pytest.mark.no_pacing

PROBED = ("s7_smart", "tecomat", "plcnext", "s7")


@pytest.fixture
async def sims() -> AsyncGenerator[dict[str, Server]]:
    """One simulator per vendor interface (SoftPLC's too, which nothing probes), all running."""
    async with AsyncExitStack() as stack:
        made: dict[str, Server] = {
            "s7_smart": S7SmartSimulator(),
            "tecomat": TecomatSimulator(bench=0),
            "plcnext": PlcnextSimulator(),
            "softplc": SoftplcSimulator(bench=0),
            "s7": S7Simulator(),
        }
        yield {key: await stack.enter_async_context(running(sim)) for key, sim in made.items()}


async def test_each_probe_knows_its_own(sims: dict[str, Server]) -> None:
    """A probe answers at its vendor's simulator only: the family offered is the right one."""
    async with aiohttp.ClientSession() as session:
        for vendor in PROBED:
            probe = probe_of(vendor)
            assert probe is not None
            for where, sim in sims.items():
                found = await probe(sim.host, sim.port, session, 1.0)
                assert (found is not None) is (where == vendor), (vendor, where)


async def test_nothing_listening(unused_tcp_port: int) -> None:
    """A closed port is a quick no, for every probe."""
    started = time.monotonic()
    async with aiohttp.ClientSession() as session:
        for vendor in PROBED:
            probe = probe_of(vendor)
            assert probe is not None
            assert await probe("127.0.0.1", unused_tcp_port, session, 3.0) is None
    assert time.monotonic() - started < 3.0


@pytest.mark.parametrize(
    ("slot", "found"), [(1, {"rack": 0, "slot": 1}), (2, {"rack": 0, "slot": 2}), (3, None)]
)
async def test_s7_slots(slot: int, found: dict[str, int] | None) -> None:
    """The S7 probe asks rack 0, slot 1 then 2, and says which answered; neither: not offered."""
    async with running(S7Simulator(slot=slot)) as sim, aiohttp.ClientSession() as session:
        probe = probe_of("s7")
        assert probe is not None
        assert await probe(sim.host, sim.port, session, 3.0) == found


def test_connection_request() -> None:
    """A TPKT of 22 bytes holding a class-0 CR from TSAP 01.00 to the TSAP asked."""
    frame = connection_request(0x0102)
    assert frame.hex() == "0300001611e00000000100c0010ac1020100c2020102"
