"""A paced PLC's poll: each request's values shown as it returns; an edit's read joins a poll.

The S7-200 SMART's transport here sends without pausing (the clock is frozen); where the test is
about a paced PLC, its pacing of one request a second is set on the class after the connect, so
the coordinator plans as for a paced PLC (how long a read takes, when a poll is due) while the
requests go at once. What is read is counted with the simulator.
"""

from __future__ import annotations

import asyncio
from datetime import timedelta
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.const import STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.util import dt as dt_util
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, async_fire_time_changed

from custom_components.plc_bridge.const import CONF_POINTS
from custom_components.plc_bridge.plc import Point, ReadResult
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from simulators.s7_smart import S7SmartSimulator
from tests.entries import DEVICE_ID, PointData, make_entry, point, poll, set_points

pytestmark = pytest.mark.no_pacing


def words(count: int, first: int = 0) -> list[PointData]:
    """Return `count` sensor points on consecutive V words from VW(2 * first)."""
    return [
        point(f"word{index}", f"Word {index}", "sensor", f"VW{2 * index}", "signed")
        for index in range(first, first + count)
    ]


def shown(hass: HomeAssistant, index: int) -> str:
    """Return what the sensor of word `index` shows."""
    state = hass.states.get(f"sensor.s7_200_smart_word_{index}")
    assert state is not None
    return state.state


class ReadNodes:
    """Counts the nodes the simulator read, request by request, and runs a look at each reply."""

    def __init__(self, sim: S7SmartSimulator) -> None:
        """Hook into the simulator's replies."""
        self.requests: list[int] = []
        self.looks: list[Any] = []
        self.look: Any = None
        sim.rewrite = self._reply

    def _reply(self, reply: dict[str, Any]) -> dict[str, Any]:
        """Note a read reply's node count (every reply of these tests that has nodes is one)."""
        data = reply.get("result", {}).get("data")
        if isinstance(data, list) and data:
            self.requests.append(len(data))
            if self.look is not None:
                self.looks.append(self.look())
        return reply

    @property
    def nodes(self) -> int:
        """Nodes read in all."""
        return sum(self.requests)


async def tick(hass: HomeAssistant, freezer: FrozenDateTimeFactory, seconds: int) -> None:
    """Move the clock on one second at a time, letting what is due run (and what it made due)."""
    for _ in range(seconds):
        freezer.tick(timedelta(seconds=1))
        for _again in range(2):
            async_fire_time_changed(hass)
            await hass.async_block_till_done(wait_background_tasks=True)


async def set_up(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, sim: S7SmartSimulator, count: int
) -> MockConfigEntry:
    """Set an entry of `count` words up, on whole seconds (as the ticks are)."""
    freezer.move_to(dt_util.utcnow().replace(microsecond=0))
    entry = make_entry(hass, sim, words(count))
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    return entry


def add_words(hass: HomeAssistant, entry: MockConfigEntry, count: int, first: int) -> None:
    """Save the device with `count` more words from word `first` (an import of points)."""
    points = dict(entry.subentries[DEVICE_ID].data[CONF_POINTS]) | dict(words(count, first))
    set_points(hass, entry, points)


async def test_each_request_shown_as_it_returns(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, freezer: FrozenDateTimeFactory
) -> None:
    """A poll of 3 requests: the first's values are shown before the second is answered."""
    entry = await set_up(hass, freezer, s7_smart_ha_sim, 96)
    coordinator = entry.runtime_data.coordinator
    for index in range(96):
        s7_smart_ha_sim.set(f"VW{2 * index}", 5)
    seen = ReadNodes(s7_smart_ha_sim)
    seen.look = lambda: (
        shown(hass, 0),
        shown(hass, 32),
        shown(hass, 95),
        coordinator.last_update_success,
    )
    await poll(hass, freezer)
    assert seen.requests == [32, 32, 32]
    assert seen.looks == [
        ("0", "0", "0", True),  # the first reply is being sent: nothing new shown yet
        ("5", "0", "0", True),  # the first request's values, the others as they were
        ("5", "5", "0", True),
    ]
    assert shown(hass, 95) == "5"
    await poll(hass, freezer)  # the poll after comes on its schedule, one poll of 3 requests
    assert seen.requests == [32] * 6


async def test_edit_joins_a_poll_due_before_its_read_would_end(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """64 points added 2 s before a poll of a paced PLC: read once, by that poll, first in it.

    Their own read (2 requests a second apart) would end after the poll is due: the poll
    starts at once instead and reads them in its first requests; no point is read twice.
    """
    entry = await set_up(hass, freezer, s7_smart_ha_sim, 4)
    monkeypatch.setattr(S7SmartClient, "request_interval", 1.0)
    reads: list[list[Point]] = []
    client = entry.runtime_data.client
    real_read = client.read

    async def recorded(points: list[Point], **kwargs: Any) -> ReadResult:
        reads.append(list(points))
        return await real_read(points, **kwargs)

    monkeypatch.setattr(client, "read", recorded)
    for index in range(4, 68):
        s7_smart_ha_sim.set(f"VW{2 * index}", 9)
    seen = ReadNodes(s7_smart_ha_sim)
    await tick(hass, freezer, 8)  # the next poll is due 2 s from now
    assert seen.requests == []
    add_words(hass, entry, 64, 4)
    await hass.async_block_till_done()
    await tick(hass, freezer, 1)  # the edits pause: the poll starts now
    assert seen.requests == [32, 32, 4]
    assert [p.address for p in reads[0][:64]] == [f"VW{2 * i}" for i in range(4, 68)]
    assert shown(hass, 67) == "9"
    await tick(hass, freezer, 8)  # no poll where the scheduled one was: it ran early
    assert seen.nodes == 68


async def test_edit_during_a_running_poll_waits_for_the_next(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Points added while a poll runs are read by a poll that starts at once after it, first.

    Not in a read of their own beside the running poll: over one paced transport the two
    would take turns, each as slow as both.
    """
    entry = await set_up(hass, freezer, s7_smart_ha_sim, 4)
    monkeypatch.setattr(S7SmartClient, "request_interval", 1.0)
    client = entry.runtime_data.client
    real_read = client.read
    reads: list[list[Point]] = []
    gate = asyncio.Event()

    async def held(points: list[Point], *, poll: bool = True, **kwargs: Any) -> ReadResult:
        reads.append(list(points))
        if poll and len(reads) == 1:
            await gate.wait()  # the PLC is still answering the poll's requests
        return await real_read(points, poll=poll, **kwargs)

    monkeypatch.setattr(client, "read", held)
    for index in range(4, 68):
        s7_smart_ha_sim.set(f"VW{2 * index}", 9)
    seen = ReadNodes(s7_smart_ha_sim)
    freezer.tick(timedelta(seconds=10))
    async_fire_time_changed(hass)  # the scheduled poll starts, and is held
    await asyncio.sleep(0)
    assert len(reads) == 1
    add_words(hass, entry, 64, 4)
    await asyncio.sleep(0)
    freezer.tick(timedelta(seconds=1))
    async_fire_time_changed(hass)  # the edits pause while the poll runs
    for _ in range(10):
        await asyncio.sleep(0)
    assert seen.requests == []  # nothing read beside the running poll
    gate.set()
    await hass.async_block_till_done(wait_background_tasks=True)
    async_fire_time_changed(hass)  # the poll after it is due at once
    await hass.async_block_till_done(wait_background_tasks=True)
    assert seen.requests == [4, 32, 32, 4]
    assert [p.address for p in reads[1][:64]] == [f"VW{2 * i}" for i in range(4, 68)]
    assert shown(hass, 67) == "9"
    assert shown(hass, 0) != STATE_UNAVAILABLE
