"""When polls start, what edits read, how long a setup waits, and whom a poll updates."""

from __future__ import annotations

from collections.abc import AsyncGenerator, Iterator
from datetime import timedelta
from itertools import pairwise
import logging
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.const import CONF_SCAN_INTERVAL, STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.util import dt as dt_util
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, async_fire_time_changed

from custom_components.plc_bridge.const import CONF_POINTS, DOMAIN
from custom_components.plc_bridge.entity import PlcEntity
from custom_components.plc_bridge.plc import Point, ReadResult
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from custom_components.plc_bridge.runtime import polling
from simulators.s7_smart import S7SmartSimulator
from tests.entries import (
    DEVICE_ID,
    PointData,
    device,
    edit_point,
    make_entry,
    point,
    poll,
    read_edits,
    set_points,
    sim_data,
    unload_all,
)
from tests.flows.forms import polling_form

pytestmark = pytest.mark.no_pacing


def words(count: int, first: int = 0) -> list[PointData]:
    """Return `count` sensor points on consecutive V words from VW(2 * first)."""
    return [
        point(f"word{index}", f"Word {index}", "sensor", f"VW{2 * index}", "signed")
        for index in range(first, first + count)
    ]


async def tick(hass: HomeAssistant, freezer: FrozenDateTimeFactory, seconds: float) -> None:
    """Move the clock on, one second at a time, and let what is due run (and what it made due)."""
    for _ in range(int(seconds)):
        freezer.tick(timedelta(seconds=1))
        for _again in range(2):
            async_fire_time_changed(hass)
            await hass.async_block_till_done(wait_background_tasks=True)


async def test_polls_start_an_interval_apart(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Every 10 s from start to start, though a poll takes 3 s; after one of 25 s, at once."""
    freezer.move_to(dt_util.utcnow().replace(microsecond=0))  # whole seconds, as the ticks
    entry = make_entry(hass, s7_smart_ha_sim, words(4))
    assert await hass.config_entries.async_setup(entry.entry_id)
    client = entry.runtime_data.client
    real_read = client.read
    lengths: Iterator[int] = iter([3, 3, 25, 3, 3, 3])
    starts: list[float] = []

    async def taking_time(points: list[Point], *, poll: bool = True, **kwargs: Any) -> ReadResult:
        if poll:  # the PLC answers `length` seconds later (its pacing, a slow link)
            starts.append(hass.loop.time())
            freezer.tick(timedelta(seconds=next(lengths, 3)))
        return await real_read(points, poll=poll, **kwargs)

    monkeypatch.setattr(client, "read", taking_time)
    await tick(hass, freezer, 80)
    gaps = [round(later - earlier) for earlier, later in pairwise(starts)]
    assert gaps[:5] == [10, 10, 25, 10, 10]
    assert entry.runtime_data.coordinator.cycle == pytest.approx(10)


async def test_ten_saves_read_once(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Ten devices saved in a row: their new points are read in one request once saving stops."""
    entry = make_entry(hass, s7_smart_ha_sim, words(4))
    assert await hass.config_entries.async_setup(entry.entry_id)
    polls, reads = entry.runtime_data.client.metrics.polls, s7_smart_ha_sim.calls["read"]
    for index in range(10):
        s7_smart_ha_sim.set(f"VW{100 + 2 * index}", 100 + index)
        points = dict(entry.subentries[DEVICE_ID].data[CONF_POINTS])
        points |= dict(words(1, 50 + index))
        set_points(hass, entry, points)
        await hass.async_block_till_done()
    assert s7_smart_ha_sim.calls["read"] == reads
    assert hass.states.get("sensor.s7_200_smart_word_59").state == STATE_UNAVAILABLE
    await read_edits(hass, freezer)
    assert s7_smart_ha_sim.calls["read"] == reads + 1
    assert entry.runtime_data.client.metrics.polls == polls  # no poll of every point
    for index in range(10):
        assert hass.states.get(f"sensor.s7_200_smart_word_{50 + index}").state == str(100 + index)


@pytest.mark.parametrize(
    "edit",
    [
        {"name": "Word zero"},  # a new name: the entity is made again, the value is known
        {"scale": 0.5},
        {"unit_of_measurement": "bar"},
    ],
)
async def test_edits_of_known_points_read_nothing(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    edit: dict[str, Any],
) -> None:
    """An edit that leaves every address and type as it was reads nothing, now or later."""
    s7_smart_ha_sim.set("VW0", 42)
    entry = make_entry(hass, s7_smart_ha_sim, words(4))
    assert await hass.config_entries.async_setup(entry.entry_id)
    reads = s7_smart_ha_sim.calls["read"]
    edit_point(hass, entry, "word0", **edit)
    hass.config_entries.async_update_entry(entry, title="Boiler PLC")
    await hass.async_block_till_done()
    await read_edits(hass, freezer)
    assert s7_smart_ha_sim.calls["read"] == reads
    shown = [s.state for s in hass.states.async_all("sensor") if s.entity_id.endswith("word_0")]
    assert shown in (["42"], ["21"])


async def test_pending_edit_read_cancelled_on_stop(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """Home Assistant stops before the edits pause: nothing is read, nothing is left running."""
    entry = make_entry(hass, s7_smart_ha_sim, words(4))
    assert await hass.config_entries.async_setup(entry.entry_id)
    reads = s7_smart_ha_sim.calls["read"]
    points = dict(entry.subentries[DEVICE_ID].data[CONF_POINTS]) | dict(words(1, 60))
    set_points(hass, entry, points)
    await hass.async_block_till_done()
    await hass.async_stop(force=True)
    freezer.tick(timedelta(seconds=polling.EDIT_DELAY * 2))
    async_fire_time_changed(hass)
    await hass.async_block_till_done(wait_background_tasks=True)
    assert s7_smart_ha_sim.calls["read"] == reads
    assert "still running" not in caplog.text


@pytest.fixture
async def paced_sim(hass: HomeAssistant) -> AsyncGenerator[S7SmartSimulator]:
    """An S7-200 SMART simulator in real time (no frozen clock), so that pacing takes time."""
    simulator = S7SmartSimulator()
    await simulator.start()
    yield simulator
    await unload_all(hass)
    await simulator.stop()


async def test_setup_returns_before_a_paced_first_read_ends(
    hass: HomeAssistant, paced_sim: S7SmartSimulator, monkeypatch: pytest.MonkeyPatch
) -> None:
    """200 points are 7 paced requests: the setup reads the first 32, the poll after the rest."""
    monkeypatch.setattr(S7SmartClient, "request_interval", 0.2)
    monkeypatch.setattr(polling, "FIRST_POLL_PACING", 0.2)  # one request's worth
    entry = make_entry(hass, paced_sim, words(200))
    assert await hass.config_entries.async_setup(entry.entry_id)
    assert entry.runtime_data.client.metrics.polls == 1  # the full poll has begun, at most
    states = [hass.states.get(f"sensor.s7_200_smart_word_{index}") for index in range(200)]
    assert all(state is not None for state in states)  # every entity is there
    assert [s.state for s in states if s is not None].count(STATE_UNAVAILABLE) == 200 - 32
    await hass.async_block_till_done(wait_background_tasks=True)
    assert paced_sim.calls["read"] == 1 + 7
    assert hass.states.get("sensor.s7_200_smart_word_199").state == "0"
    assert hass.states.get("sensor.s7_200_smart_operating_mode").state == "run"


async def test_poll_updates_only_changed_points(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """One value changed: its entity and the PLC's own are updated, the other points' are not."""
    updated: list[str] = []
    original = PlcEntity._handle_coordinator_update

    def counting(entity: PlcEntity) -> None:
        updated.append(entity.unique_id or "")
        original(entity)

    monkeypatch.setattr(PlcEntity, "_handle_coordinator_update", counting)
    entry = make_entry(hass, s7_smart_ha_sim, words(5))
    assert await hass.config_entries.async_setup(entry.entry_id)
    await poll(hass, freezer)
    updated.clear()
    s7_smart_ha_sim.set("VW4", 7)
    await poll(hass, freezer)
    points = sorted(key.rsplit("_", 1)[-1] for key in updated if "word" in key)
    assert points == ["word2"]
    assert len(updated) > 1  # the PLC's operating mode and clock follow every poll
    assert hass.states.get("sensor.s7_200_smart_word_2").state == "7"


async def test_failed_poll_updates_every_entity(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """The PLC stops answering: every entity goes unavailable, and comes back with it."""
    caplog.set_level(logging.ERROR)
    entry: MockConfigEntry = make_entry(hass, s7_smart_ha_sim, words(3))
    assert await hass.config_entries.async_setup(entry.entry_id)
    s7_smart_ha_sim.malformed = True
    await poll(hass, freezer)
    assert hass.states.get("sensor.s7_200_smart_word_1").state == STATE_UNAVAILABLE
    s7_smart_ha_sim.malformed = False
    await poll(hass, freezer)
    assert hass.states.get("sensor.s7_200_smart_word_1").state == "0"


async def test_options_form_shows_the_real_cycle(
    hass: HomeAssistant, flow_sim: S7SmartSimulator, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Stored 10 s, but 1,000 points take 32 requests a second apart: polls start every 32 s."""
    monkeypatch.setattr(S7SmartClient, "request_interval", 1.0)
    entry = MockConfigEntry(
        domain=DOMAIN,
        data=sim_data(flow_sim),
        options={CONF_SCAN_INTERVAL: 10.0},
        subentries_data=[device(words(1000))],
        version=2,
    )
    entry.add_to_hass(hass)
    result = await polling_form(hass, entry)
    assert result["description_placeholders"]["cycle"] == "32"
    assert result["description_placeholders"]["minimum"] == "32"


async def test_many_changes_update_in_slices(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A poll that changed more points than a slice updates them over several loop turns."""
    monkeypatch.setattr(polling, "UPDATE_SLICE", 2)
    entry = make_entry(hass, s7_smart_ha_sim, words(5))
    assert await hass.config_entries.async_setup(entry.entry_id)
    coordinator = entry.runtime_data.coordinator
    slices: list[int] = []
    original = coordinator._update

    def counting(updates: list[Any]) -> None:
        slices.append(len(updates))
        original(updates)

    monkeypatch.setattr(coordinator, "_update", counting)
    for index in range(5):
        s7_smart_ha_sim.set(f"VW{2 * index}", 10 + index)
    await poll(hass, freezer)
    assert max(slices) == 2
    assert sum(slices) >= 5
    for index in range(5):
        assert hass.states.get(f"sensor.s7_200_smart_word_{index}").state == str(10 + index)


async def test_quiet_poll_keeps_its_results(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, freezer: FrozenDateTimeFactory
) -> None:
    """Unchanged values keep the result objects of the poll before; a changed one is new."""
    entry = make_entry(hass, s7_smart_ha_sim, words(3))
    assert await hass.config_entries.async_setup(entry.entry_id)
    coordinator = entry.runtime_data.coordinator
    before = dict(coordinator.data.values)
    s7_smart_ha_sim.set("VW2", 5)
    await poll(hass, freezer)
    after = coordinator.data.values
    assert after[Point("VW0", "signed")] is before[Point("VW0", "signed")]
    assert after[Point("VW2", "signed")] is not before[Point("VW2", "signed")]
    assert after[Point("VW2", "signed")].value == 5
