"""Command layouts the PLC cannot keep are refused where they are made, on their field.

A command is never read only, a button has no poll class, a cover's or valve's travel time is
bounded and shared by its parts, and a SoftPLC command bit never shares its word (written
whole) with a read-only bit: each refused in the forms, the tables and the pasted PLC file,
with nothing stored; the write guard names the command and the reason.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from homeassistant.config_entries import SOURCE_USER
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.exceptions import ServiceValidationError
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import CONF_POINTS, DOMAIN, SUBENTRY_DEVICE
from custom_components.plc_bridge.model.config_file import dump_config
from custom_components.plc_bridge.model.point_table import export_points, parse_points
from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors import client_class
from simulators.softplc import SoftplcSimulator
from tests.entries import PointData, call, point
from tests.flows.forms import (
    MACHINE,
    entity_page,
    error_message,
    on_page,
    page_shown,
    step,
    strings_at,
)
from tests.harness import make_softplc_entry, softplc_data
from tests.test_config_file import CONFIG, paste

pytestmark = pytest.mark.no_pacing

SOFTPLC = client_class("softplc")
SMART = client_class("s7_smart")
COMMAND = point("cmd", "Lamp", "switch", "B3:3/0", "BOOL")
STATE = point("state", "Lamp on", "binary_sensor", "B3:3/1", "BOOL", read_only=True)
"""The usual SoftPLC layout: a command bit beside a read-only state bit, in one B3 word."""


@pytest.fixture
def softplc_entry(hass: HomeAssistant, softplc_ha_sim: SoftplcSimulator) -> MockConfigEntry:
    """A SoftPLC entry whose machine holds the read-only state bit B3:3/1 (not set up)."""
    return make_softplc_entry(hass, softplc_ha_sim, [STATE])


def key_only(key: str, placeholders: Mapping[str, str]) -> str:
    """Word a table's problem as its key alone."""
    return key


def fields(result: Any) -> set[str]:
    """Return the names of a form's fields."""
    return {str(marker) for marker in result["data_schema"].schema}


def machines(entry: MockConfigEntry) -> list[dict[str, Any]]:
    """Return every stored point of the entry's machines."""
    return [
        data
        for subentry in entry.subentries.values()
        for data in subentry.data.get(CONF_POINTS, {}).values()
    ]


async def menu_of(hass: HomeAssistant, entry: MockConfigEntry) -> Any:
    """Open a new machine of the entry and return its menu."""
    result = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_DEVICE), context={"source": SOURCE_USER}
    )
    return await step(hass, result, {"name": "Garage"})


async def composite(hass: HomeAssistant, entry: MockConfigEntry, platform: str) -> Any:
    """Open a new machine's page for an entity of several addresses of this kind."""
    return await entity_page(hass, await menu_of(hass, entry), platform)


async def fill(hass: HomeAssistant, result: Any, platform: str, **values: Any) -> Any:
    """Submit the entity's page with these fields (name: Door), each put in its section."""
    return await step(hass, result, on_page(platform, {"name": "Door", **values}))


def page_fields(result: Any) -> set[str]:
    """Return every field of an entity's page, those inside its sections included."""
    names: set[str] = set()
    for marker, shown in result["data_schema"].schema.items():
        inner = getattr(getattr(shown, "schema", None), "schema", None)
        names |= {str(key) for key in inner} if isinstance(inner, dict) else {str(marker)}
    return names


async def test_written_parts_never_read_only(
    hass: HomeAssistant, flow_entry: MockConfigEntry
) -> None:
    """The entity's page offers no "Read only": a cover's commands and a climate's set point
    are stored writable, what is only read is stored read only."""
    result = await composite(hass, flow_entry, "cover")
    assert "read_only" not in page_fields(result)
    menu = await fill(hass, result, "cover", open="Q0.4", closed_limit="I0.1")
    assert menu["type"] is FlowResultType.MENU, menu.get("errors")
    result = await entity_page(hass, menu, "climate")
    menu = await fill(hass, result, "climate", target_temperature="VW40")
    await step(hass, menu, {"next_step_id": "save"})
    by_role = {data["role"]: data["read_only"] for data in machines(flow_entry)}
    assert by_role == {"open": False, "closed_limit": True, "target_temperature": False}


async def test_button_never_read_only_and_without_poll_class(
    hass: HomeAssistant, flow_entry: MockConfigEntry
) -> None:
    """A button's form offers no poll class and refuses "Read only"; its data has no class."""
    result = await step(hass, await menu_of(hass, flow_entry), {"next_step_id": "point"})
    where = {"name": "Bell", "platform": "button", "address": "Q0.5", "data_type": "signed"}
    result = await step(hass, result, where)
    assert result["step_id"] == "details"
    assert "poll" not in fields(result)
    result = await step(hass, result, {"read_only": True})
    assert result["errors"] == {"read_only": "command_read_only"}
    menu = await step(hass, result, {"read_only": False, "pulse": 0.5})
    await step(hass, menu, {"next_step_id": "save"})
    (bell,) = machines(flow_entry)
    assert bell["pulse"] == 0.5
    assert "poll" not in bell


def test_table_refuses_read_only_commands_and_classed_buttons() -> None:
    """A table's read-only command row and a button row with a poll class fail on their lines."""
    table = (
        "name,address,platform,role,read_only,poll,pulse\n"
        "Door,Q0.4,cover,open,true,,\n"
        "Door,I0.1,cover,closed_limit,true,,\n"
        "Bell,Q0.5,button,,false,fast,0.5\n"
        "Horn,Q0.6,button,,false,normal,\n"
    )
    points, errors = parse_points(SMART, table, describe=key_only)
    assert points == []
    assert errors == [(2, "command_read_only"), (4, "poll_not_for_button")]
    points, errors = parse_points(
        SMART, table.replace("open,true", "open,false"), describe=key_only
    )
    assert errors == [(4, "poll_not_for_button")]


async def test_travel_time_on_the_cover_form(
    hass: HomeAssistant, flow_entry: MockConfigEntry
) -> None:
    """A cover's travel time is bounded on its field, then stored on every part and exported."""
    result = await composite(hass, flow_entry, "cover")
    assert "travel_time" in fields(result)
    parts = {"open": "Q0.4", "close": "Q0.5", "closed_limit": "I0.1"}
    result = await fill(hass, result, "cover", **parts, travel_time=700)
    assert result["errors"] == {"travel_time": "travel_time_out_of_range"}
    result = await fill(hass, result, "cover", **parts, travel_time=25)
    await step(hass, result, {"next_step_id": "save"})
    stored = machines(flow_entry)
    assert {data["travel_time"] for data in stored} == {25.0}
    table = export_points(stored)
    assert table.splitlines()[0].endswith(",travel_time")
    again, errors = parse_points(SMART, table)
    assert errors == []
    assert [data["travel_time"] for data in again] == [25.0] * 3


async def test_travel_time_asked_of_covers_and_valves_only(
    hass: HomeAssistant, flow_entry: MockConfigEntry
) -> None:
    """A fan's page has no travel time; a valve's has."""
    assert "travel_time" not in fields(await composite(hass, flow_entry, "fan"))
    assert "travel_time" in fields(await composite(hass, flow_entry, "valve"))


def test_table_travel_time_bounded_and_shared() -> None:
    """A table refuses a travel time out of bounds, on a point that does not travel, or two."""
    head = "name,address,platform,role,travel_time\n"
    rows = {
        "Door,Q0.4,cover,open,0.5\n": [(2, "travel_time_out_of_range")],
        "Level,VW10,sensor,,30\n": [(2, "travel_time_not_here")],
        "Door,Q0.4,cover,open,30\nDoor,Q0.5,cover,close,40\n": [(2, "travel_time_differs")],
        "Door,Q0.4,cover,open,30\nDoor,Q0.5,cover,close,\n": [],
        "Door,Q0.4,valve,open,0\n": [],
    }
    for lines, expected in rows.items():
        points, errors = parse_points(SMART, head + lines, describe=key_only)
        assert errors == expected, lines
        assert all("travel_time" not in data for data in points if "30" not in lines)


def test_softplc_bits_of_one_word_are_apart_but_written_together() -> None:
    """Two bits of a word cover different data; writing either writes the whole word."""
    command, state = (SOFTPLC.validate_point(Point(a, "BOOL")) for a in ("B3:3/0", "B3:3/1"))
    assert not SOFTPLC.footprint(command).overlaps(SOFTPLC.footprint(state))
    assert SOFTPLC.write_footprint(command).overlaps(SOFTPLC.footprint(state))
    word = SOFTPLC.validate_point(Point("B3:3", "INT"))
    assert SOFTPLC.write_footprint(word) == SOFTPLC.footprint(word)
    assert SOFTPLC.footprint(word).overlaps(SOFTPLC.footprint(state))
    assert not SOFTPLC.write_footprint(command).overlaps(
        SOFTPLC.footprint(SOFTPLC.validate_point(Point("B3:4/0", "BOOL")))
    )
    smart = SMART.validate_point(Point("V60.0", "signed"))
    assert SMART.write_footprint(smart) == SMART.footprint(smart)


async def test_write_guard_names_the_command_and_the_reason(
    hass: HomeAssistant, softplc_ha_sim: SoftplcSimulator
) -> None:
    """A write of the command bit is refused naming it, the read-only bit and why; none sent."""
    entry = make_softplc_entry(hass, softplc_ha_sim, [COMMAND, STATE])
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    before = softplc_ha_sim.requests
    with pytest.raises(ServiceValidationError) as err:
        await call(
            hass, "write", entry, points=[{"address": "B3:3/0", "data_type": "BOOL", "value": True}]
        )
    assert str(err.value) == (
        "The PLC writes whole words: B3:3/0 shares its word with the read-only point B3:3/1; "
        "nothing was sent"
    )
    assert softplc_ha_sim.requests == before


async def test_softplc_switch_form_refuses_the_shared_word(
    hass: HomeAssistant, softplc_entry: MockConfigEntry
) -> None:
    """A switch of a state and a command in one word: refused on the command, with the reason."""
    result = await composite(hass, softplc_entry, "switch")
    result = await fill(hass, result, "switch", state="B3:4/1", command="B3:3/0")
    assert result["errors"] == {"on_off": "in_on_off"}
    assert error_message(result, "on_off", *MACHINE).startswith(
        "Command: The PLC writes whole words: B3:3/0 shares its word with the read-only point "
        "B3:3/1"
    )
    result = await fill(hass, result, "switch", state="B3:4/1", command="B3:4/0")
    assert result["errors"] == {"on_off": "in_on_off"}
    assert "B3:4/1" in error_message(result, "on_off", *MACHINE)
    menu = await fill(hass, result, "switch", state="B3:4/1", command="B3:5/0")
    assert menu["type"] is FlowResultType.MENU, menu.get("errors")
    assert len(machines(softplc_entry)) == 1


async def test_softplc_point_form_refuses_the_shared_word(
    hass: HomeAssistant, softplc_entry: MockConfigEntry
) -> None:
    """A switch at B3:3/0 is refused on its address; a read-only bit under a command too."""
    menu = await menu_of(hass, softplc_entry)
    result = await step(hass, menu, {"next_step_id": "point"})
    where = {"name": "Lamp", "platform": "switch", "address": "B3:3/0", "data_type": "BOOL"}
    result = await step(hass, result, where)
    assert result["errors"] == {"address": "writes_read_only"}
    result = await step(hass, result, {**where, "platform": "sensor"})
    assert result["step_id"] == "details"
    result = await step(hass, result, {"read_only": False})
    assert result["type"] is FlowResultType.MENU  # a sensor is only shown: the guard's
    result = await step(hass, result, {"next_step_id": "point"})
    where = {"name": "Fan", "platform": "switch", "address": "B3:6/0", "data_type": "BOOL"}
    result = await step(hass, await step(hass, result, where), {"read_only": False})
    result = await step(hass, result, {"next_step_id": "point"})
    limit = {"name": "Fan on", "platform": "binary_sensor", "address": "B3:6/3"}
    result = await step(hass, result, {**limit, "data_type": "BOOL"})
    assert result["errors"] == {"address": "writes_read_only"}
    assert error_message(result, "address", *MACHINE).startswith(
        "The PLC writes whole words: B3:6/0 shares its word with the read-only point B3:6/3"
    )


def test_softplc_table_refuses_the_shared_word() -> None:
    """A table's command row sharing a word with a read-only row fails on the command's line."""
    table = (
        "name,address,data_type,platform,role,read_only\n"
        "Lamp,B3:3/1,BOOL,switch,state,true\n"
        "Lamp,B3:3/0,BOOL,switch,command,false\n"
        "Fan,B3:4/0,BOOL,switch,,false\n"
    )
    points, errors = parse_points(SOFTPLC, table)
    assert points == []
    assert errors == [(3, "writes_read_only (B3:3/0, B3:3/1)")]
    stored = [COMMAND[1]]
    points, errors = parse_points(SOFTPLC, "name,address\nLimit,B3:3/5\n", plc=stored)
    assert errors == [(2, "writes_read_only (B3:3/0, B3:3/5)")]


@pytest.mark.parametrize(
    ("points", "error", "on_line"),
    [
        ([COMMAND, STATE], "config_writes_read_only", "address: "),
        (
            [point("open", "Door", "cover", "B3:7/0", "BOOL", role="open", read_only=True)],
            "config_command_read_only",
            "read_only: true",
        ),
        (
            [point("open", "Door", "cover", "B3:7/0", "BOOL", role="open", travel_time=900.0)],
            "config_travel_time",
            "travel_time: 900.0",
        ),
    ],
)
async def test_pasted_file_runs_the_same_checks(
    hass: HomeAssistant,
    softplc_ha_sim: SoftplcSimulator,
    points: list[PointData],
    error: str,
    on_line: str,
) -> None:
    """A pasted PLC file with such a layout is refused with the reason on its line; no PLC."""
    entry = make_softplc_entry(hass, softplc_ha_sim, points)
    text = dump_config(entry)
    assert await hass.config_entries.async_remove(entry.entry_id)
    result = await paste(hass, text)
    assert result["errors"] == {"configuration": error}
    assert strings_at(*CONFIG, "error", error).format(**result["description_placeholders"])
    line = int(result["description_placeholders"]["line"])
    assert on_line in text.splitlines()[line - 1]
    assert hass.config_entries.async_entries(DOMAIN) == []
    assert softplc_data(softplc_ha_sim)


async def test_edited_part_sets_the_whole_entitys_travel_time(
    hass: HomeAssistant, flow_entry: MockConfigEntry
) -> None:
    """Editing one part's travel time changes every part's; out of bounds is refused on it."""
    result = await composite(hass, flow_entry, "valve")
    result = await fill(hass, result, "valve", open="Q0.4", close="Q0.5", travel_time=20)
    await step(hass, result, {"next_step_id": "save"})
    subentry_id = next(iter(flow_entry.subentries))
    menu = await hass.config_entries.subentries.async_init(
        (flow_entry.entry_id, SUBENTRY_DEVICE),
        context={"source": "reconfigure", "subentry_id": subentry_id},
    )
    result = await step(hass, menu, {"next_step_id": "edit"})
    part = next(iter(flow_entry.subentries[subentry_id].data[CONF_POINTS]))
    result = await step(hass, result, {"point": part})
    assert result["step_id"] == "composite_entity"
    page = page_shown(result)
    assert page["travel_time"] == 20
    result = await step(hass, result, {**page, "travel_time": 601})
    assert result["errors"] == {"travel_time": "travel_time_out_of_range"}
    menu = await step(hass, result, {**page, "travel_time": 40})
    await step(hass, menu, {"next_step_id": "save"})
    assert {data["travel_time"] for data in machines(flow_entry)} == {40.0}
