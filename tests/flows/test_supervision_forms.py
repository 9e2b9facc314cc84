"""A supervision time is offered, bounded and shared where it is made: form, table, PLC file."""

from __future__ import annotations

from homeassistant.core import HomeAssistant
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import DOMAIN
from custom_components.plc_bridge.model.config_file import dump_config
from custom_components.plc_bridge.model.point_table import export_points, parse_points
from simulators.s7_smart import S7SmartSimulator
from tests.entries import make_entry, point
from tests.flows.forms import step, strings_at
from tests.flows.test_command_layouts import (
    SMART,
    composite,
    fields,
    fill,
    key_only,
    machines,
)
from tests.test_config_file import CONFIG, paste

pytestmark = pytest.mark.no_pacing


async def test_supervision_on_the_switch_form(
    hass: HomeAssistant, flow_entry: MockConfigEntry
) -> None:
    """Bounded on its field, then stored on every part, exported and read back from the table."""
    result = await composite(hass, flow_entry, "switch")
    assert "supervision" in fields(result)
    parts = {"state": "I0.1", "command": "Q0.4"}
    result = await fill(hass, result, "switch", **parts, supervision=700)
    assert result["errors"] == {"supervision": "supervision_out_of_range"}
    result = await fill(hass, result, "switch", **parts, supervision=10)
    await step(hass, result, {"next_step_id": "save"})
    stored = machines(flow_entry)
    assert {data["supervision"] for data in stored} == {10.0}
    table = export_points(stored)
    assert "supervision" in table.splitlines()[0].split(",")
    again, errors = parse_points(SMART, table)
    assert errors == []
    assert [data["supervision"] for data in again] == [10.0] * 2


@pytest.mark.parametrize(
    ("platform", "offered"),
    [("light", True), ("fan", True), ("climate", True), ("cover", False), ("valve", False)],
)
async def test_supervision_asked_of_supervised_kinds_only(
    hass: HomeAssistant, flow_entry: MockConfigEntry, platform: str, offered: bool
) -> None:
    """Lights, fans and climates are asked; covers and valves have their travel time."""
    assert ("supervision" in fields(await composite(hass, flow_entry, platform))) is offered


def test_table_supervision_bounded_and_shared() -> None:
    """A table refuses a time out of bounds, on a kind not supervised, or two for one entity."""
    head = "name,address,platform,role,read_only,supervision\n"
    rows = {
        "Pump,Q0.4,switch,command,false,0.5\n": [(2, "supervision_out_of_range")],
        "Pump,Q0.4,switch,command,false,601\n": [(2, "supervision_out_of_range")],
        "Level,VW10,sensor,,true,30\n": [(2, "supervision_not_here")],
        "Plain,Q0.4,switch,,false,30\n": [(2, "supervision_not_here")],
        "Door,Q0.4,cover,open,false,30\n": [(2, "supervision_not_here")],
        "Pump,Q0.4,switch,command,false,30\nPump,I0.1,switch,state,true,40\n": [
            (2, "supervision_differs")
        ],
        "Pump,Q0.4,switch,command,false,30\nPump,I0.1,switch,state,true,\n": [],
        "Lamp,Q0.4,light,command,false,0\n": [],
    }
    for lines, expected in rows.items():
        points, errors = parse_points(SMART, head + lines, describe=key_only)
        assert errors == expected, lines
        assert all("supervision" not in data for data in points if "30" not in lines)


@pytest.mark.parametrize(
    ("supervision", "platform", "role"),
    [(900.0, "switch", "command"), (30.0, "cover", "open"), (30.0, "switch", None)],
)
async def test_pasted_file_refuses_a_bad_supervision(
    hass: HomeAssistant,
    flow_sim: S7SmartSimulator,
    supervision: float,
    platform: str,
    role: str | None,
) -> None:
    """A pasted PLC file with a time out of bounds or on a kind without it adds no PLC."""
    data = {"supervision": supervision} | ({"role": role} if role else {})
    entry = make_entry(hass, flow_sim, [point("p", "Pump", platform, "Q0.4", "signed", **data)])
    text = dump_config(entry)
    assert await hass.config_entries.async_remove(entry.entry_id)
    result = await paste(hass, text)
    assert result["errors"] == {"configuration": "config_supervision"}
    assert strings_at(*CONFIG, "error", "config_supervision").format(
        **result["description_placeholders"]
    )
    line = int(result["description_placeholders"]["line"])
    assert f"supervision: {supervision}" in text.splitlines()[line - 1]
    assert hass.config_entries.async_entries(DOMAIN) == []


async def test_pasted_file_keeps_a_good_supervision(
    hass: HomeAssistant, flow_sim: S7SmartSimulator
) -> None:
    """A pasted PLC file with a switch supervised for 30 s passes the check."""
    points = [
        point("s", "Pump", "switch", "I0.1", "signed", role="state", read_only=True),
        point("c", "Pump", "switch", "Q0.4", "signed", role="command", supervision=30.0),
    ]
    entry = make_entry(hass, flow_sim, points)
    text = dump_config(entry)
    assert "supervision: 30" in text
    assert await hass.config_entries.async_remove(entry.entry_id)
    result = await paste(hass, text)
    assert result.get("errors") in (None, {})
