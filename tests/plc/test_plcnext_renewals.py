"""PLCnext against the simulator: overlapping calls over a lost session, unknown names, groups."""

from __future__ import annotations

import asyncio
import math
import random
from typing import TYPE_CHECKING

import pytest

from custom_components.plc_bridge.plc import PlcConnectionError, PlcError, PlcProtocolError, Point
from custom_components.plc_bridge.plc.vendors.plcnext import PlcnextClient
from custom_components.plc_bridge.plc.vendors.plcnext.groups import GROUPS_KEPT
from simulators.plcnext import PlcnextSimulator
from simulators.plcnext.demo import default_program

if TYPE_CHECKING:
    from .plcnext_fixtures import ConfigFactory

POINTS = [
    Point("MainInstance.Temperature", "REAL"),
    Point("MainInstance.Pump", "BOOL"),
    Point("MainInstance.Levels[2]", "INT"),
]


async def test_overlapping_calls_share_one_new_session(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient
) -> None:
    """Five reads in flight when the session is lost: all succeed on one new session.

    Before: the first renewal cleared the session id before the new one existed, so the
    others' 410 answers were taken as final and four reads failed.
    """
    await plcnext_client.read(POINTS, poll=False)
    plcnext_sim.access.expire_sessions()
    before = plcnext_sim.calls.get("POST sessions", 0)
    results = await asyncio.gather(
        *(plcnext_client.read(POINTS, poll=False) for _ in range(5)), return_exceptions=True
    )
    assert [type(result).__name__ for result in results] == ["ReadResult"] * 5
    assert all(all(r.ok for r in result.values.values()) for result in results)  # type: ignore[union-attr]
    assert plcnext_sim.calls.get("POST sessions", 0) - before == 1
    assert len(plcnext_sim.access.sessions) == 1


@pytest.mark.parametrize("entries", [False, True], ids=["404-whole", "per-entry"])
async def test_unknown_names_among_many(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient, entries: bool
) -> None:
    """5 unknown names among 1,000: found in O(log N) requests, no group left behind.

    Before: 87 requests, and 39 groups of halves stayed registered on the PLC.
    """
    plcnext_sim.program = default_program(1000)
    plcnext_sim.unknown_entries = entries
    points = [Point(f"Bench.Value{index}", "DINT") for index in range(1000)]
    gone = sorted(random.Random(19).sample(range(1000), 5))
    for index in gone:
        points[index] = Point(f"Bench.Gone{index}", "DINT")
    result = await plcnext_client.read(points)
    failed = [p.address for p, r in result.values.items() if not r.ok]
    assert failed == [f"Bench.Gone{index}" for index in gone]
    assert all(
        r.value == int(p.address.removeprefix("Bench.Value"))
        for p, r in result.values.items()
        if r.ok
    )
    # register (404), per name: the rest whole + halving, a last whole read, register, group read
    budget = 4 if entries else 3 + 5 * (math.ceil(math.log2(1000)) + 1) + 1
    assert plcnext_client.metrics.last_poll_requests <= budget
    assert len(plcnext_sim.groups) == 1
    await plcnext_client.read(points)
    assert plcnext_client.metrics.last_poll_requests == 1


async def test_changed_points_unregister_the_oldest_group(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient
) -> None:
    """Polls of other points keep GROUPS_KEPT groups (poll classes alternate); no more.

    A poll of a kept group's points is one group read again; a fifth set of points
    unregisters the group read longest ago.
    """
    sets = [POINTS, POINTS[:2], POINTS[1:], POINTS[:1], POINTS[2:]]
    for points in sets[:GROUPS_KEPT]:
        await plcnext_client.read(points)
    assert len(plcnext_sim.groups) == GROUPS_KEPT
    await plcnext_client.read(POINTS[:2])
    assert plcnext_client.metrics.last_poll_requests == 1
    await plcnext_client.read(sets[GROUPS_KEPT])
    assert len(plcnext_sim.groups) == GROUPS_KEPT
    await plcnext_client.read(POINTS)  # unregistered: registered again
    assert plcnext_client.metrics.last_poll_requests > 1
    assert len(plcnext_sim.groups) == GROUPS_KEPT


@pytest.mark.parametrize("status", [200, 500])
@pytest.mark.parametrize("where", ["variables", "dictionary"])
async def test_deeply_nested_answer(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient, where: str, status: int
) -> None:
    """An answer nested deeper than Python parses is a PlcProtocolError or the status's error.

    Before: json.loads's RecursionError escaped, and a setup ended without retry.
    """
    plcnext_sim.answer_with = (status, b"[" * 100_000 + b"]" * 100_000)
    call = plcnext_client.read(POINTS, poll=False) if where == "variables" else None
    with pytest.raises(PlcError) as caught:
        await (call or plcnext_client.browse())
    assert isinstance(caught.value, PlcConnectionError if status == 500 else PlcProtocolError)


async def test_a_reused_group_is_left_registered(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient
) -> None:
    """An identical group the PLC reused (200: another client's) is not unregistered."""
    status, other = plcnext_sim.groups.register(
        "Arp.Plc.Eclr/", ["MainInstance.Temperature", "MainInstance.Pump", "MainInstance.Clock"]
    )
    assert status == 201
    await plcnext_client.read(POINTS[:2])
    await plcnext_client.read(POINTS)
    await plcnext_client.close()
    assert list(plcnext_sim.groups.registered) == [other]


async def test_station_with_a_session_takes_another_id(
    plcnext_sim: PlcnextSimulator, plcnext_config: ConfigFactory
) -> None:
    """A 409 for a station that has a session (PyREST): another station id, once."""
    plcnext_sim.station_conflicts = True
    client = PlcnextClient(plcnext_config())
    try:
        station = client._rest().station
        plcnext_sim.access.open(str(station), 60_000)
        await client.connect()
        assert client._rest().station != station
        assert client._rest().session_id in plcnext_sim.access.sessions
    finally:
        await client.close()
