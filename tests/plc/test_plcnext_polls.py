"""PLCnext polls against the simulator: parsing kept per client, short paths, names' case."""

from __future__ import annotations

import pytest

from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors.plcnext import PlcnextClient
from custom_components.plc_bridge.plc.vendors.plcnext.paths import parse_path
from simulators.plcnext import PlcnextSimulator
from simulators.plcnext.demo import default_program


async def test_a_poll_of_5000_points_parses_nothing_again(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient
) -> None:
    """The second poll of 5,000 points parses no path: they are kept for the client's polls.

    Before: a cache of 4,096 paths shared by all clients was outgrown, and every poll of
    5,000 points parsed all of them again.
    """
    plcnext_sim.program = default_program(5000)
    points = [Point(f"Bench.Value{index}", "DINT") for index in range(5000)]
    await plcnext_client.read(points)
    before = parse_path.cache_info()
    result = await plcnext_client.read(points)
    after = parse_path.cache_info()
    assert (after.hits, after.misses) == (before.hits, before.misses)
    assert [r.value for r in result.values.values()] == list(range(5000))
    assert plcnext_client.metrics.last_poll_requests == 1


async def test_group_registered_relative_to_its_component(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient
) -> None:
    """Paths of one component are registered with its pathPrefix (the Groups page's example)."""
    await plcnext_client.read([Point("MainInstance.Pump", "BOOL"), Point("GlobalFlag", "BOOL")])
    (group,) = plcnext_sim.groups.registered.values()
    assert group.prefix == "Arp.Plc.Eclr/"
    assert group.paths == ["MainInstance.Pump", "GlobalFlag", "MainInstance.Clock"]  # + clock


@pytest.mark.parametrize("case_sensitive", [False, True], ids=["any-case", "as-declared"])
@pytest.mark.parametrize("declared", [False, True], ids=["echo-as-asked", "echo-declared"])
@pytest.mark.parametrize("poll", [True, False], ids=["group", "variables"])
async def test_names_differing_in_case_are_not_merged(
    plcnext_sim: PlcnextSimulator,
    plcnext_client: PlcnextClient,
    case_sensitive: bool,
    declared: bool,
    poll: bool,
) -> None:
    """`Pump` and `PUMP` are asked as typed; each point gets only what its own name gets.

    Before: paths were keyed in lower case, so `PUMP` was never sent and showed `Pump`'s value
    on a PLC whose names are case-sensitive.
    """
    plcnext_sim.program.case_sensitive = case_sensitive
    plcnext_sim.declared_spelling = declared
    plcnext_sim.set("MainInstance.Pump", True)
    typed, other = Point("MainInstance.Pump", "BOOL"), Point("MainInstance.PUMP", "BOOL")
    result = await plcnext_client.read([other, typed], poll=poll)
    assert result.values[typed].value is True
    if case_sensitive:
        assert not result.values[other].ok
    else:
        assert result.values[other].value is True


async def test_results_kept_only_for_the_same_value(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient
) -> None:
    """A poll reuses a point's result only for the same JSON value: 0.0 then -0.0 shows both."""
    setpoint, pump = Point("MainInstance.Setpoint", "REAL"), Point("MainInstance.Pump", "BOOL")
    shown: list[tuple[object, object]] = []
    for real, flag in ((0.0, False), (-0.0, False), (-0.0, True), (1.5, True)):
        plcnext_sim.set("MainInstance.Setpoint", real)
        plcnext_sim.set("MainInstance.Pump", flag)
        result = await plcnext_client.read([setpoint, pump])
        shown.append((result.values[setpoint].value, result.values[pump].value))
    assert [str(value) for value, _flag in shown] == ["0.0", "-0.0", "-0.0", "1.5"]
    assert [flag for _value, flag in shown] == [False, False, True, True]
