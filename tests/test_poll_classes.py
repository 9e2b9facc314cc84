"""Poll classes: fast, normal and slow points each read at their interval, in one read a poll."""

from __future__ import annotations

from collections.abc import Sequence
from datetime import timedelta
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.number import ATTR_VALUE, SERVICE_SET_VALUE
from homeassistant.config_entries import SOURCE_USER
from homeassistant.const import ATTR_ENTITY_ID, CONF_SCAN_INTERVAL
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.setup import async_setup_component
from homeassistant.util import dt as dt_util
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, async_fire_time_changed

from custom_components.plc_bridge.const import CONF_POINTS, DOMAIN, SUBENTRY_DEVICE
from custom_components.plc_bridge.plc import PlcClient, Point, ReadResult
from custom_components.plc_bridge.plc.vendors import client_class
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from custom_components.plc_bridge.point_table import export_points, parse_points, point_order
from custom_components.plc_bridge.points import PointConfig, point_classes
from simulators.s7 import S7Simulator
from simulators.s7_smart import S7SmartSimulator
from simulators.tecomat import TecomatSimulator

from .flow_fixtures import MACHINE, error_message, smart_data, translated
from .ha_fixtures import PointData, device, edit_point, make_entry, point
from .s7_ha_fixtures import make_s7_entry
from .tecomat_ha_fixtures import make_tecomat_entry

SMART = client_class("s7_smart")
OPTIONS = ("options",)
SLOW_OPTIONS = {CONF_SCAN_INTERVAL: 10.0, "fast_interval": 1.0, "slow_interval": 30.0}
"""Fast every second, normal every 10 s (every 10th poll), slow every 30 s (every 30th)."""


@pytest.fixture
def reads(monkeypatch: pytest.MonkeyPatch) -> list[list[Point]]:
    """Record the points of every poll's read, from the setup's first poll on."""
    polls: list[list[Point]] = []
    original = PlcClient.read

    async def recorded(
        self: PlcClient, points: Sequence[Point], *, poll: bool = True
    ) -> ReadResult:
        if poll:
            polls.append(list(points))
        return await original(self, points, poll=poll)

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
    s7_smart_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    reads: list[list[Point]],
) -> None:
    """Each poll is one request holding the due points only (S7-200 SMART: 32 nodes a read)."""
    words = [point(f"w{i}", f"Word {i}", "sensor", f"VW{2 * i}", "signed") for i in range(3)]
    entry = make_entry(hass, s7_smart_sim, classed(words, ("fast", "normal", "slow")))
    before = s7_smart_sim.calls["read"]
    await check_cadence(
        hass,
        freezer,
        entry,
        reads,
        (Point("VW0", "signed"), Point("VW2", "signed"), Point("VW4", "signed")),
    )
    assert s7_smart_sim.calls["read"] - before == len(reads)


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
    tecomat_sim: TecomatSimulator,
    freezer: FrozenDateTimeFactory,
    reads: list[list[Point]],
) -> None:
    """The same cadence on a Tecomat (TecoApi)."""
    points = [
        point("int", "Int", "sensor", "plcData.varInt", "INT", poll="fast"),
        point("inside", "Inside", "sensor", "Main.myObject2.value", "REAL"),
        point("udint", "Salary", "sensor", "myObject.salary", "UDINT", poll="slow"),
    ]
    entry = make_tecomat_entry(hass, tecomat_sim, points)
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
    s7_smart_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    reads: list[list[Point]],
) -> None:
    """Without fast or slow points: every 10 s, every point, the same list each time."""
    words = [point(f"w{i}", f"Word {i}", "sensor", f"VW{2 * i}", "signed") for i in range(3)]
    entry = make_entry(hass, s7_smart_sim, words)
    await set_up_classes(hass, freezer, entry)
    assert entry.runtime_data.coordinator.update_interval == timedelta(seconds=10)
    await tick(hass, freezer, 31)
    assert len(reads) == 4
    assert all(len(points) == 3 for points in reads)


async def test_edited_class_applies_without_reload(
    hass: HomeAssistant,
    s7_smart_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    reads: list[list[Point]],
    setups: list[str],
) -> None:
    """A point made fast is read every second from the next second on; nothing reloads."""
    words = [point(f"w{i}", f"Word {i}", "sensor", f"VW{2 * i}", "signed") for i in range(3)]
    entry = make_entry(hass, s7_smart_sim, words)
    await set_up_classes(hass, freezer, entry)
    runtime = entry.runtime_data
    await tick(hass, freezer, 3)
    assert len(reads) == 1
    s7_smart_sim.set("VW0", 77)
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
    s7_smart_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    reads: list[list[Point]],
) -> None:
    """A written slow point is read back by the refresh after the write; its class waits."""
    points = [
        point("fast", "Fast", "sensor", "VW0", "signed", poll="fast"),
        point("other", "Other", "sensor", "VW22", "signed", poll="slow"),
        point("setpoint", "Setpoint", "number", "VW20", "signed", poll="slow", min=0.0, max=99.0),
    ]
    entry = make_entry(hass, s7_smart_sim, points)
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


def words(count: int, poll: str) -> list[PointData]:
    """Return `count` word sensors of one poll class."""
    return [
        point(f"w{i}", f"Word {i}", "sensor", f"VW{2 * i}", "signed", poll=poll)
        for i in range(count)
    ]


@pytest.mark.parametrize(
    ("given", "field", "error", "message"),
    [
        ({"fast_interval": 3.0}, "fast_interval", "fast_interval_too_short", "every 4 s"),
        ({"fast_interval": 12.0}, "fast_interval", "fast_above_normal", "longer than"),
        ({"slow_interval": 5.0}, "slow_interval", "slow_below_normal", "shorter than"),
        ({CONF_SCAN_INTERVAL: 5.0, "slow_interval": 4.5}, "slow_interval", "slow_below_normal", ""),
        ({CONF_SCAN_INTERVAL: 3.0}, CONF_SCAN_INTERVAL, "scan_interval_too_short", "every 4 s"),
    ],
)
async def test_options_refuse_bad_intervals(
    hass: HomeAssistant,
    flow_sim: S7SmartSimulator,
    monkeypatch: pytest.MonkeyPatch,
    *,
    given: dict[str, float],
    field: str,
    error: str,
    message: str,
) -> None:
    """100 fast points take 4 requests at one a second: refused below 4 s, or out of order."""
    monkeypatch.setattr(S7SmartClient, "request_interval", 1.0)
    entry = MockConfigEntry(
        domain=DOMAIN,
        data=smart_data(flow_sim),
        subentries_data=[device(words(100, "fast"))],
        version=2,
    )
    entry.add_to_hass(hass)
    result = await hass.config_entries.options.async_init(entry.entry_id)
    values = {"fast_interval": 4.0, CONF_SCAN_INTERVAL: 10.0, "slow_interval": 60.0}
    result = translated(
        await hass.config_entries.options.async_configure(result["flow_id"], values | given),
        *OPTIONS,
    )
    assert result["errors"][field] == error
    assert message in error_message(result, field, *OPTIONS)
    if field != CONF_SCAN_INTERVAL:  # fast 4 s is above a normal 3 s: said too
        assert result["errors"] == {field: error}
    assert dict(entry.options) == {}
    result = await hass.config_entries.options.async_configure(result["flow_id"], values)
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert dict(entry.options) == values


async def test_fast_default_follows_the_pace(
    hass: HomeAssistant, flow_sim: S7SmartSimulator, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The fast interval offered is 1 s, or what the vendor's pace allows where that is more."""
    monkeypatch.setattr(S7SmartClient, "request_interval", 1.0)
    entry = MockConfigEntry(
        domain=DOMAIN,
        data=smart_data(flow_sim),
        subentries_data=[device(words(40, "fast"))],
        version=2,
    )
    entry.add_to_hass(hass)
    result = await hass.config_entries.options.async_init(entry.entry_id)
    shown = {str(key): key.description["suggested_value"] for key in result["data_schema"].schema}
    assert shown == {"fast_interval": 2.0, CONF_SCAN_INTERVAL: 10.0, "slow_interval": 60.0}
    assert result["description_placeholders"]["fast_minimum"] == "2"


TABLE = (
    "name,address,data_type,platform,poll\n"
    "Limit switch,I0.1,signed,binary_sensor,fast\n"
    "Pressure,VW10,signed,sensor,\n"
    "Outdoor,VW12,signed,sensor,Slow\n"
    "Level,VW14,signed,sensor,normal\n"
)


def test_table_round_trip_with_poll() -> None:
    """The poll column is read (case-insensitive, empty or normal: normal) and written back."""
    points, errors = parse_points(SMART, TABLE)
    assert errors == []
    assert [data.get("poll") for data in points] == ["fast", None, "slow", None]
    text = export_points(points)
    assert "poll" in text.splitlines()[0].split(",")
    again, errors = parse_points(SMART, text)
    assert errors == []
    assert sorted(again, key=point_order) == sorted(points, key=point_order)
    assert export_points(again) == text


def test_table_refuses_an_unknown_class() -> None:
    """A poll cell that names no class is refused on its line."""
    _, errors = parse_points(SMART, "name,address,poll\nPressure,VW10,often\n")
    assert [(line, text.split()[0]) for line, text in errors] == [(2, "poll_invalid")]


def test_parts_of_an_entity_share_the_fastest_class() -> None:
    """A cover whose position is fast is read fast whole; a point of its own keeps its class."""

    def part(pid: str, address: str, role: str, poll: str | None = None) -> PointConfig:
        data: dict[str, Any] = {"name": "Shutter", "platform": "cover", "role": role}
        data |= {"address": address, "data_type": "signed"} | ({"poll": poll} if poll else {})
        return PointConfig(pid, "machine", data)

    configs = {
        "a": part("a", "VW40", "position", "fast"),
        "b": part("b", "Q0.4", "open"),
        "c": part("c", "Q0.6", "stop", "slow"),
        "d": PointConfig(
            "d",
            "machine",
            {"name": "Outdoor", "platform": "sensor", "address": "VW50"}
            | {"data_type": "signed", "poll": "slow"},
        ),
    }
    classes = point_classes(configs)
    assert classes == {
        Point("VW40", "signed"): "fast",
        Point("Q0.4", "signed"): "fast",
        Point("Q0.6", "signed"): "fast",
        Point("VW50", "signed"): "slow",
    }


async def test_composite_form_sets_every_part(
    hass: HomeAssistant, flow_sim: S7SmartSimulator
) -> None:
    """The class chosen for a cover is every part's; an edited part changes the whole cover."""
    entry = MockConfigEntry(domain=DOMAIN, data=smart_data(flow_sim), version=2)
    entry.add_to_hass(hass)
    menu = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_DEVICE), context={"source": SOURCE_USER}
    )
    menu = await step(hass, menu, {"name": "Garage"})
    result = await step(hass, menu, {"next_step_id": "composite"})
    assert "poll" in fields(result)
    result = await step(hass, result, {"platform": "cover", "name": "Door", "poll": "fast"})
    result = await step(hass, result, {"position": "VW40", "open": "Q0.4"})
    assert "poll" not in fields(result)  # set once, for the whole entity
    result = await step(hass, result, {"scale": 1, "offset": 0, "read_only": True})
    menu = await step(hass, result, {"read_only": False})
    points = await saved(hass, entry, menu)
    assert {data["poll"] for data in points.values()} == {"fast"}
    menu = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_DEVICE),
        context={"source": "reconfigure", "subentry_id": next(iter(entry.subentries))},
    )
    result = await step(hass, menu, {"next_step_id": "edit"})
    part = next(iter(points))
    result = await step(hass, result, {"point": part})
    assert fields(result) == {"address", "data_type"}  # a part's address comes first
    where = {key: points[part][key] for key in ("address", "data_type")}
    result = await step(hass, result, where)
    assert "poll" in fields(result)
    values = {"scale": 1, "offset": 0} if "scale" in fields(result) else {}
    menu = await step(hass, result, {**values, "read_only": True, "poll": "slow"})
    points = await saved(hass, entry, menu)
    assert {data.get("poll") for data in points.values()} == {"slow"}


async def step(hass: HomeAssistant, result: Any, values: dict[str, Any]) -> Any:
    """Submit a machine form or pick a menu option; every field and error must be translated."""
    result = await hass.config_entries.subentries.async_configure(result["flow_id"], values)
    return translated(result, *MACHINE)


def fields(result: Any) -> set[str]:
    """Return the names of a form's fields."""
    return {str(marker) for marker in result["data_schema"].schema}


async def saved(hass: HomeAssistant, entry: MockConfigEntry, menu: Any) -> dict[str, Any]:
    """Save the machine from its menu; return its stored points."""
    await step(hass, menu, {"next_step_id": "save"})
    (machine,) = entry.subentries.values()
    return dict(machine.data[CONF_POINTS])


async def test_update_entity_reads_its_point(
    hass: HomeAssistant,
    s7_smart_sim: S7SmartSimulator,
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
    entry = make_entry(hass, s7_smart_sim, points)
    await set_up_classes(hass, freezer, entry)
    await tick(hass, freezer, 3)
    s7_smart_sim.set("VW2", 12)
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
