"""Poll classes: fast, normal and slow points each read at their interval, in one read a poll."""

from __future__ import annotations

from collections.abc import Sequence
from datetime import timedelta
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.number import ATTR_VALUE, SERVICE_SET_VALUE
from homeassistant.const import ATTR_ENTITY_ID, CONF_SCAN_INTERVAL
from homeassistant.core import HomeAssistant
from homeassistant.setup import async_setup_component
from homeassistant.util import dt as dt_util
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, async_fire_time_changed

from custom_components.plc_bridge.plc import PlcClient, Point, ReadResult
from simulators.s7 import S7Simulator
from simulators.s7_smart import S7SmartSimulator
from simulators.tecomat import TecomatSimulator
from tests.entries import PointData, edit_point, make_entry, point
from tests.harness import make_s7_entry, make_tecomat_entry

pytestmark = pytest.mark.no_pacing

SLOW_OPTIONS = {CONF_SCAN_INTERVAL: 10.0, "fast_interval": 1.0, "slow_interval": 30.0}
"""Fast every second, normal every 10 s (every 10th poll), slow every 30 s (every 30th)."""


@pytest.fixture
def reads(monkeypatch: pytest.MonkeyPatch) -> list[list[Point]]:
    """Record the points of every poll's read, from the setup's first poll on."""
    polls: list[list[Point]] = []
    original = PlcClient.read

    async def recorded(
        self: PlcClient, points: Sequence[Point], *, poll: bool = True, **kwargs: Any
    ) -> ReadResult:
        if poll:
            polls.append(list(points))
        return await original(self, points, poll=poll, **kwargs)

    monkeypatch.setattr(PlcClient, "read", recorded)
    return polls


async def tick(hass: HomeAssistant, freezer: FrozenDateTimeFactory, seconds: int) -> None:
    """Move the clock on one second at a time, letting each due poll run."""
    for _ in range(seconds):
        freezer.tick(timedelta(seconds=1))
        async_fire_time_changed(hass)
        await hass.async_block_till_done(wait_background_tasks=True)


async def set_up_classes(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, entry: MockConfigEntry
) -> None:
    """Give the entry the fast, normal and slow intervals of SLOW_OPTIONS and set it up."""
    freezer.move_to(dt_util.utcnow().replace(microsecond=0))
    hass.config_entries.async_update_entry(entry, options=SLOW_OPTIONS)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()


def classed(points: list[PointData], classes: Sequence[str]) -> list[PointData]:
    """Return the points with these poll classes (normal stored as none, as the forms do)."""
    return [
        (pid, data | ({"poll": name} if name != "normal" else {}))
        for (pid, data), name in zip(points, classes, strict=True)
    ]


def where(polls: list[list[Point]], point: Point) -> list[int]:
    """Return the indexes of the polls that read the point."""
    return [index for index, points in enumerate(polls) if point in points]


async def check_cadence(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    entry: MockConfigEntry,
    reads: list[list[Point]],
    points: tuple[Point, Point, Point],
) -> None:
    """Fast in every poll, normal in every 10th, slow in every 30th; one read a poll."""
    fast, normal, slow = points
    await set_up_classes(hass, freezer, entry)
    coordinator = entry.runtime_data.coordinator
    assert coordinator.update_interval == timedelta(seconds=1)
    polls = entry.runtime_data.client.metrics.polls
    await tick(hass, freezer, 62)
    assert entry.runtime_data.client.metrics.polls - polls == len(reads) - 1
    assert len(reads) >= 61
    taken = reads[:61]
    assert where(taken, fast) == list(range(61))
    assert where(taken, normal) == list(range(0, 61, 10))
    assert where(taken, slow) == [0, 30, 60]
    assert all(len(points) == 1 for index, points in enumerate(taken) if index % 10)
    state = entry.runtime_data.coordinator.data.values
    assert all(state[point].ok for point in (fast, normal, slow))  # kept between their reads


async def test_classes_on_the_s7_200_smart(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    reads: list[list[Point]],
) -> None:
    """Each poll is one request holding the due points only (S7-200 SMART: 32 nodes a read)."""
    words = [point(f"w{i}", f"Word {i}", "sensor", f"VW{2 * i}", "signed") for i in range(3)]
    entry = make_entry(hass, s7_smart_ha_sim, classed(words, ("fast", "normal", "slow")))
    before = s7_smart_ha_sim.calls["read"]
    await check_cadence(
        hass,
        freezer,
        entry,
        reads,
        (Point("VW0", "signed"), Point("VW2", "signed"), Point("VW4", "signed")),
    )
    assert s7_smart_ha_sim.calls["read"] - before == len(reads)


async def test_classes_on_the_s7(
    hass: HomeAssistant,
    s7_ha_sim: S7Simulator,
    freezer: FrozenDateTimeFactory,
    reads: list[list[Point]],
) -> None:
    """The same cadence on an S7 (ISO-on-TCP)."""
    points = [
        point("level", "Level", "sensor", "DB1.DBW2", "INT", poll="fast"),
        point("temperature", "Temperature", "sensor", "DB1.DBD8", "REAL"),
        point("counter", "Counter", "sensor", "MW20", "INT", poll="slow"),
    ]
    entry = make_s7_entry(hass, s7_ha_sim, points)
    await check_cadence(
        hass,
        freezer,
        entry,
        reads,
        (Point("DB1.DBW2", "INT"), Point("DB1.DBD8", "REAL"), Point("MW20", "INT")),
    )


async def test_classes_on_the_tecomat(
    hass: HomeAssistant,
    tecomat_ha_sim: TecomatSimulator,
    freezer: FrozenDateTimeFactory,
    reads: list[list[Point]],
) -> None:
    """The same cadence on a Tecomat (TecoApi)."""
    points = [
        point("int", "Int", "sensor", "plcData.varInt", "INT", poll="fast"),
        point("inside", "Inside", "sensor", "Main.myObject2.value", "REAL"),
        point("udint", "Salary", "sensor", "myObject.salary", "UDINT", poll="slow"),
    ]
    entry = make_tecomat_entry(hass, tecomat_ha_sim, points)
    await check_cadence(
        hass,
        freezer,
        entry,
        reads,
        (
            Point("plcData.varInt", "INT"),
            Point("Main.myObject2.value", "REAL"),
            Point("myObject.salary", "UDINT"),
        ),
    )


async def test_only_normal_points_poll_as_before(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    reads: list[list[Point]],
) -> None:
    """Without fast or slow points: every 10 s, every point, the same list each time."""
    words = [point(f"w{i}", f"Word {i}", "sensor", f"VW{2 * i}", "signed") for i in range(3)]
    entry = make_entry(hass, s7_smart_ha_sim, words)
    await set_up_classes(hass, freezer, entry)
    assert entry.runtime_data.coordinator.update_interval == timedelta(seconds=10)
    await tick(hass, freezer, 31)
    assert len(reads) == 4
    assert all(len(points) == 3 for points in reads)


async def test_edited_class_applies_without_reload(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    reads: list[list[Point]],
    setups: list[str],
) -> None:
    """A point made fast is read every second from the next second on; nothing reloads."""
    words = [point(f"w{i}", f"Word {i}", "sensor", f"VW{2 * i}", "signed") for i in range(3)]
    entry = make_entry(hass, s7_smart_ha_sim, words)
    await set_up_classes(hass, freezer, entry)
    runtime = entry.runtime_data
    await tick(hass, freezer, 3)
    assert len(reads) == 1
    s7_smart_ha_sim.set("VW0", 77)
    edit_point(hass, entry, "w0", poll="fast")
    await hass.async_block_till_done()
    await tick(hass, freezer, 5)
    assert entry.runtime_data is runtime
    assert setups == [entry.entry_id]
    assert runtime.coordinator.update_interval == timedelta(seconds=1)
    after = reads[1:]
    assert len(after) >= 3
    assert all(points == [Point("VW0", "signed")] for points in after)
    assert hass.states.get("sensor.s7_200_smart_word_0").state == "77"


async def test_write_reads_back_a_slow_point(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    reads: list[list[Point]],
) -> None:
    """A written slow point is read back by the refresh after the write; its class waits."""
    points = [
        point("fast", "Fast", "sensor", "VW0", "signed", poll="fast"),
        point("other", "Other", "sensor", "VW22", "signed", poll="slow"),
        point("setpoint", "Setpoint", "number", "VW20", "signed", poll="slow", min=0.0, max=99.0),
    ]
    entry = make_entry(hass, s7_smart_ha_sim, points)
    await set_up_classes(hass, freezer, entry)
    await tick(hass, freezer, 5)
    count = len(reads)
    await hass.services.async_call(
        "number",
        SERVICE_SET_VALUE,
        {ATTR_ENTITY_ID: "number.s7_200_smart_setpoint", ATTR_VALUE: 42},
        blocking=True,
    )
    await hass.async_block_till_done()
    assert len(reads) == count + 1
    assert Point("VW20", "signed") in reads[-1]
    assert Point("VW22", "signed") not in reads[-1]
    assert hass.states.get("number.s7_200_smart_setpoint").state == "42"
    await tick(hass, freezer, 3)
    assert all(Point("VW20", "signed") not in points for points in reads[count + 1 :])


async def test_update_entity_reads_its_point(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    reads: list[list[Point]],
) -> None:
    """`homeassistant.update_entity` on a slow sensor reads it now, not its whole class."""
    await async_setup_component(hass, "homeassistant", {})
    points = [
        point("fast", "Fast", "sensor", "VW0", "signed", poll="fast"),
        point("outdoor", "Outdoor", "sensor", "VW2", "signed", poll="slow"),
        point("other", "Other", "sensor", "VW4", "signed", poll="slow"),
    ]
    entry = make_entry(hass, s7_smart_ha_sim, points)
    await set_up_classes(hass, freezer, entry)
    await tick(hass, freezer, 3)
    s7_smart_ha_sim.set("VW2", 12)
    count = len(reads)
    await hass.services.async_call(
        "homeassistant",
        "update_entity",
        {ATTR_ENTITY_ID: "sensor.s7_200_smart_outdoor"},
        blocking=True,
    )
    await hass.async_block_till_done()
    assert len(reads) == count + 1
    assert Point("VW2", "signed") in reads[-1]
    assert Point("VW4", "signed") not in reads[-1]
    assert hass.states.get("sensor.s7_200_smart_outdoor").state == "12"
