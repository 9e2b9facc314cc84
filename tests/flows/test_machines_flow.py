"""The device flow's point forms for a select, a button and an alarm word, as a user fills them."""

from __future__ import annotations

from typing import Any

from homeassistant.config_entries import SOURCE_USER
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import CONF_POINTS, SUBENTRY_DEVICE
from tests.flows.forms import translated

pytestmark = pytest.mark.no_pacing

DEVICE = ("config_subentries", SUBENTRY_DEVICE)


async def step(hass: HomeAssistant, result: Any, values: dict[str, Any]) -> Any:
    """Submit a form or pick a menu option; every field and error must be translated."""
    result = await hass.config_entries.subentries.async_configure(result["flow_id"], values)
    return translated(result, *DEVICE)


def fields(result: Any) -> set[str]:
    """Return the names of a form's fields."""
    return {str(marker) for marker in result["data_schema"].schema}


async def test_select_button_and_alarm_word(
    hass: HomeAssistant, flow_entry: MockConfigEntry
) -> None:
    menu = await hass.config_entries.subentries.async_init(
        (flow_entry.entry_id, SUBENTRY_DEVICE), context={"source": SOURCE_USER}
    )
    menu = await step(hass, menu, {"name": "Boiler"})

    result = await step(hass, menu, {"next_step_id": "point"})
    base = {"name": "Mode", "platform": "select", "address": "VW30", "data_type": "signed"}
    result = await step(hass, result, base)
    assert fields(result) == {"value_map", "read_only", "poll", "availability"}
    result = await step(hass, result, {"value_map": "0=Off;Auto", "read_only": False})
    assert result["errors"] == {"value_map": "map_not_a_pair"}
    assert result["description_placeholders"]["pair"] == "Auto"
    menu = await step(hass, result, {"value_map": "0=Off\n1=Auto\n2=Manual", "read_only": False})
    assert menu["type"] is FlowResultType.MENU

    result = await step(hass, menu, {"next_step_id": "point"})
    base = {"name": "Start", "platform": "button", "address": "Q0.2", "data_type": "signed"}
    result = await step(hass, result, base)
    assert fields(result) == {"pulse", "read_only", "availability"}  # no poll class
    menu = await step(hass, result, {"pulse": 0.5, "read_only": False})

    result = await step(hass, menu, {"next_step_id": "point"})
    base = {"name": "Alarms", "platform": "event", "address": "VW70", "data_type": "unsigned"}
    result = await step(hass, result, base)
    assert fields(result) == {"bits", "read_only", "poll", "availability"}
    menu = await step(hass, result, {"bits": "0=Overheat;3=Low water", "read_only": True})

    result = await step(hass, menu, {"next_step_id": "save"})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    (device,) = flow_entry.subentries.values()
    points = {data["name"]: data for data in device.data[CONF_POINTS].values()}
    assert points["Mode"]["value_map"] == "0=Off;1=Auto;2=Manual"
    assert points["Start"]["pulse"] == 0.5
    assert points["Alarms"]["bits"] == "0=Overheat;3=Low water"
    assert points["Alarms"]["read_only"] is True
