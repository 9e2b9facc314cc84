"""PLCnext sessions: the timeout the PLC grants is kept, and the session kept alive within it.

Each test runs against every reading of row 20 of simulators/plcnext/READINGS.md (granted as
asked or shorter; named in the create answer or only in the sessions report),
fixture `plcnext_sessions`.
"""

from __future__ import annotations

import asyncio

from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors.plcnext import PlcnextClient
from simulators.plcnext import PlcnextSimulator
from tests.loopback import ConfigFactory, connected

from .plcnext_fixtures import plcnext_sessions

__all__ = ["plcnext_sessions"]  # a fixture, imported to be found

type Sessions = tuple[PlcnextSimulator, ConfigFactory]
POINTS = [Point("MainInstance.Temperature", "REAL"), Point("MainInstance.Pump", "BOOL")]
POLLS = 3
GAP = 1.3  # seconds between polls: longer than a shorter grant (1 s), as a slow poll is


async def test_one_session_over_polls_longer_apart_than_granted(
    plcnext_sessions: Sessions,
) -> None:
    """Polls further apart than the granted timeout: one session for all of them, kept alive
    in between; every poll is one request. Before: a new session (and the 410 that told)
    at every poll."""
    sim, settings = plcnext_sessions
    async with connected(PlcnextClient(settings(poll_interval=GAP))) as client:
        await client.read(POINTS)
        created = sim.access.created
        for _poll in range(POLLS):
            await asyncio.sleep(GAP)
            result = await client.read(POINTS)
            assert all(outcome.ok for outcome in result.values.values())
            assert client.metrics.last_poll_requests == 1
        assert sim.access.created == created == 1
        assert client.metrics.session_renewals == 0
        maintained = sim.calls.get("POST sessions", 0) - created
        if sim.session_cap is None:
            assert maintained == 0  # the polls alone keep a session granted as asked
        else:
            assert maintained <= POLLS * 2 * GAP / sim.session_cap + 1
    assert not sim.access.sessions  # closed: deleted, and no keep-alive left running


async def test_polls_within_the_grant_cost_no_keep_alive(plcnext_sessions: Sessions) -> None:
    """Polls closer than half the granted timeout keep the session by themselves: no
    keep-alive is sent."""
    sim, settings = plcnext_sessions
    async with connected(PlcnextClient(settings(poll_interval=0.2))) as client:
        for _poll in range(4):
            await client.read(POINTS)
            await asyncio.sleep(0.2)
        assert sim.calls.get("POST sessions", 0) == sim.access.created == 1
