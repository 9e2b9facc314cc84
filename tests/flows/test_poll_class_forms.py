"""Poll classes in the forms: the options' intervals, the point table's column, composites."""

from __future__ import annotations

from typing import Any

from homeassistant.config_entries import SOURCE_USER
from homeassistant.const import CONF_SCAN_INTERVAL
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import CONF_POINTS, DOMAIN, SUBENTRY_DEVICE
from custom_components.plc_bridge.model.composite import point_classes
from custom_components.plc_bridge.model.point_table import export_points, parse_points, point_order
from custom_components.plc_bridge.model.points import PointConfig
from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors import client_class
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from simulators.s7_smart import S7SmartSimulator
from tests.entries import PointData, device, point, sim_data
from tests.flows.forms import (
    MACHINE,
    entity_page,
    error_message,
    on_page,
    page_shown,
    polling_form,
    translated,
)
from tests.flows.test_command_layouts import page_fields

pytestmark = pytest.mark.no_pacing

SMART = client_class("s7_smart")
OPTIONS = ("options",)


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
        data=sim_data(flow_sim),
        subentries_data=[device(words(100, "fast"))],
        version=2,
    )
    entry.add_to_hass(hass)
    result = await polling_form(hass, entry)
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
        data=sim_data(flow_sim),
        subentries_data=[device(words(40, "fast"))],
        version=2,
    )
    entry.add_to_hass(hass)
    result = await polling_form(hass, entry)
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
    entry = MockConfigEntry(domain=DOMAIN, data=sim_data(flow_sim), version=2)
    entry.add_to_hass(hass)
    menu = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_DEVICE), context={"source": SOURCE_USER}
    )
    menu = await step(hass, menu, {"name": "Garage"})
    result = await entity_page(hass, menu, "cover")
    assert "poll" in page_fields(result)  # once, for the whole entity
    values = {"name": "Door", "poll": "fast", "position": "VW40", "open": "Q0.4"}
    menu = await step(hass, result, on_page("cover", values))
    points = await saved(hass, entry, menu)
    assert {data["poll"] for data in points.values()} == {"fast"}
    menu = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_DEVICE),
        context={"source": "reconfigure", "subentry_id": next(iter(entry.subentries))},
    )
    result = await step(hass, menu, {"next_step_id": "edit"})
    part = next(iter(points))
    result = await step(hass, result, {"point": part})
    page = page_shown(result)
    assert page["entity_options"]["poll"] == "fast"
    page["entity_options"]["poll"] = "slow"  # one field, for every part
    menu = await step(hass, result, page)
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
