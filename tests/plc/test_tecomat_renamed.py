"""Renamed variables: found in few requests, asked again on their own timers (issue 19)."""

from __future__ import annotations

from collections.abc import AsyncGenerator, Callable
import time

import pytest

from custom_components.plc_bridge.plc import PlcAddressError, Point
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient, client as client_module
from simulators.tecomat import TecomatSimulator
from tests.loopback import running

from .tecomat_fixtures import ConfigFactory

BENCH = [Point(f"BENCH.V{index}", "INT") for index in range(1000)]
NAME = Point("plcName", "STRING")


@pytest.fixture
async def bench_sim() -> AsyncGenerator[TecomatSimulator]:
    """A simulator whose BENCH structure holds 1,000 INTs."""
    async with running(TecomatSimulator(bench=1000)) as sim:
        yield sim


@pytest.fixture
def clock(monkeypatch: pytest.MonkeyPatch) -> Callable[[float], None]:
    """Set how many seconds the client's clock runs ahead of the real one."""

    def ahead(seconds: float) -> None:
        monkeypatch.setattr(client_module, "monotonic", lambda: time.monotonic() + seconds)

    return ahead


@pytest.mark.parametrize("leaf_names", [False, True], ids=["whole-path", "stopping-item"])
async def test_renamed_structure_of_1000_points(
    bench_sim: TecomatSimulator,
    tecomat_config: ConfigFactory,
    clock: Callable[[float], None],
    leaf_names: bool,
) -> None:
    """A structure renamed under 1,000 points costs two requests, then one a timer, not 96.

    Before: 101 requests at the first poll (a failed request and a probe per URI) and 96 again
    at every 60 s.
    """
    bench_sim.leaf_names = leaf_names
    bench_sim.rename_stamps = False  # the worst case: nothing says the program changed
    client = TecomatClient(tecomat_config(port=bench_sim.port))
    try:
        await client.connect()
        bench_sim.rename("BENCH", "BENCH2")
        before = bench_sim.calls["GetObject"]
        result = await client.read([*BENCH, NAME])
        # the refused URI, the probe of BENCH (whole paths only), then plcName alone
        assert bench_sim.calls["GetObject"] - before == (2 if leaf_names else 3)
        assert all(isinstance(result.values[point].error, PlcAddressError) for point in BENCH)
        assert result.values[NAME].value == "myFoxtrot"
        # timers: 2 s, then doubling (4 s, 8 s): short at first, cheap while it stays gone
        for ahead, asked in ((1, 1), (2.5, 2), (5, 1), (7, 2), (14, 1), (16, 2)):
            clock(ahead)
            before = bench_sim.calls["GetObject"]
            await client.read([*BENCH, NAME])
            assert bench_sim.calls["GetObject"] - before == asked, ahead
        bench_sim.rename("BENCH2", "BENCH")
        clock(16 + 17)
        result = await client.read([*BENCH, NAME])
        assert [result.values[point].value for point in BENCH[:3]] == [0, 1, 2]
    finally:
        await client.close()


async def test_each_unknown_variable_has_its_own_timer(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient, clock: Callable[[float], None]
) -> None:
    """A variable renamed back is read again 60 s after it went, whatever went missing since.

    Before: one timer for all, restarted by each variable that went missing: 118 s unavailable.
    """
    tecomat_sim.rename_stamps = False
    kind, desc = Point("plcType", "UINT"), Point("plcDesc", "STRING")
    points = [NAME, kind, desc]
    tecomat_sim.rename("plcType", "plcKind")
    await tecomat_client.read(points)
    clock(50)
    tecomat_sim.rename("plcDesc", "plcText")
    assert isinstance((await tecomat_client.read(points)).values[desc].error, PlcAddressError)
    tecomat_sim.rename("plcKind", "plcType")
    clock(61)
    result = await tecomat_client.read(points)
    assert result.values[kind].value == 2005
    assert isinstance(result.values[desc].error, PlcAddressError)


async def test_a_new_program_stamp_asks_again_at_once(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient, clock: Callable[[float], None]
) -> None:
    """GetInfo's stamp (3.2) changes with the program: every unknown variable is asked again."""
    kind = Point("plcType", "UINT")
    tecomat_sim.rename("plcType", "plcKind")
    await tecomat_client.read([NAME, kind])
    tecomat_sim.rename("plcKind", "plcType")  # a new stamp
    clock(tecomat_client.status_interval)  # GetInfo is due; the variable's own timer too
    tecomat_client._unknown._entries["plctype"].due += 1000  # so only the stamp can tell
    result = await tecomat_client.read([NAME, kind])
    assert result.values[kind].value == 2005


@pytest.mark.parametrize("stamps", [True, False], ids=["new-stamp", "same-stamp"])
async def test_renamed_back_shows_within_a_poll_or_two(
    tecomat_sim: TecomatSimulator,
    tecomat_client: TecomatClient,
    clock: Callable[[float], None],
    stamps: bool,
) -> None:
    """Renamed away and back 3 s later: shown again at the next poll after its short timer.

    Before: asked again 60 s after it went, the stamp read once a minute (issue 23: unavailable
    3.4-73 s after the rename back).
    """
    tecomat_sim.rename_stamps = stamps
    kind = Point("plcType", "UINT")
    clock(0)
    tecomat_sim.rename("plcType", "plcKind")
    assert isinstance((await tecomat_client.read([NAME, kind])).values[kind].error, Exception)
    clock(1)
    assert not (await tecomat_client.read([NAME, kind])).values[kind].ok
    tecomat_sim.rename("plcKind", "plcType")
    clock(3)  # the next poll (1 s polls): the first timer (2 s) is due
    assert (await tecomat_client.read([NAME, kind])).values[kind].value == 2005


async def test_a_variable_gone_for_good_costs_few_requests(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient, clock: Callable[[float], None]
) -> None:
    """Polled every second for 10 minutes: asked again on doubling timers, not every poll."""
    tecomat_sim.rename_stamps = False
    kind = Point("plcType", "UINT")
    tecomat_sim.rename("plcType", "plcKind")
    clock(0)
    await tecomat_client.read([NAME, kind])
    before = tecomat_client.metrics.requests
    for second in range(1, 601):
        clock(second)
        await tecomat_client.read([NAME, kind])
    # 600 polls, 10 GetInfo (60 s), and about log2(300 / 2) + 600 / 300 re-asks (a probe and
    # a stamp check each)
    assert tecomat_client.metrics.requests - before <= 600 + 10 + 2 * 12


async def test_read_clock_after_a_poll_asks_getinfo(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    """A poll that read GetInfo (a variable went missing) leaves read_clock its own GetInfo."""
    tecomat_sim.rename("plcType", "plcKind")
    await tecomat_client.read([NAME, Point("plcType", "UINT")])
    before = tecomat_sim.calls["GetInfo"]
    await tecomat_client.read_clock()
    assert tecomat_sim.calls["GetInfo"] == before + 1
