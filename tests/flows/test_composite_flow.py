"""The device flow's steps for an entity of several addresses, as a user fills them."""

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


async def start(hass: HomeAssistant, flow_entry: MockConfigEntry, platform: str, name: str) -> Any:
    """Open the device flow and choose an entity of several addresses of this kind."""
    menu = await hass.config_entries.subentries.async_init(
        (flow_entry.entry_id, SUBENTRY_DEVICE), context={"source": SOURCE_USER}
    )
    menu = await step(hass, menu, {"name": "Garage"})
    assert "composite" in menu["menu_options"]
    result = await step(hass, menu, {"next_step_id": "composite"})
    return await step(hass, result, {"platform": platform, "name": name})


async def test_cover_from_the_menu(hass: HomeAssistant, flow_entry: MockConfigEntry) -> None:
    """Only the cover's parts are asked, then each part's own settings; all join the machine."""
    result = await start(hass, flow_entry, "cover", "Door")
    assert "open" in fields(result)
    assert "target_temperature" not in fields(result)
    result = await step(hass, result, {"position": "AIW16", "open": "IW0"})
    assert result["errors"] == {"open": "address_not_writable"}
    result = await step(hass, result, {"position": "VW40", "open": "Q0.4", "stop": "Q0.6"})
    assert result["step_id"] == "composite_part"
    assert result["description_placeholders"]["role"] == "position"
    assert {"raw_min", "shown_max", "invert", "read_only"} <= fields(result)
    part = {"raw_min": 0, "raw_max": 27648, "shown_min": 0, "shown_max": 100}
    result = await step(hass, result, {**part, "scale": 1, "offset": 0, "read_only": True})
    assert result["description_placeholders"]["role"] == "open"
    assert "pulse" in fields(result)
    result = await step(hass, result, {"read_only": False})
    result = await step(hass, result, {"pulse": 1.5, "read_only": False})
    assert result["type"] is FlowResultType.MENU
    result = await step(hass, result, {"next_step_id": "save"})
    (device,) = flow_entry.subentries.values()
    parts = {data["role"]: data for data in device.data[CONF_POINTS].values()}
    assert set(parts) == {"position", "open", "stop"}
    assert {data["name"] for data in parts.values()} == {"Door"}
    assert parts["position"]["raw_max"] == 27648
    assert parts["position"]["read_only"] is True
    assert parts["stop"]["pulse"] == 1.5


async def test_climate_needs_a_part_that_shows(
    hass: HomeAssistant, flow_entry: MockConfigEntry
) -> None:
    """An entity of an action map alone shows nothing: the form says which parts it needs."""
    result = await start(hass, flow_entry, "climate", "Boiler")
    result = await step(hass, result, {"hvac_action": "VW56"})
    assert result["errors"] == {"base": "role_missing"}
    result = await step(hass, result, {"hvac_mode": "VW54"})
    result = await step(hass, result, {"value_map": "0=off;1=warm", "read_only": False})
    assert result["errors"] == {"value_map": "role_labels"}
    result = await step(hass, result, {"value_map": "0=off;1=heat", "read_only": False})
    assert result["type"] is FlowResultType.MENU


async def test_edit_a_part(hass: HomeAssistant, flow_entry: MockConfigEntry) -> None:
    """Editing a part asks its address and settings again, keeps its role and its entity."""
    result = await start(hass, flow_entry, "switch", "Hall")
    result = await step(hass, result, {"state": "Q0.3", "command": "M1.1"})
    result = await step(hass, result, {"invert": False, "read_only": True})
    menu = await step(hass, result, {"pulse": 0.5, "read_only": False})
    points = await saved(hass, flow_entry, menu)
    (command,) = (pid for pid, data in points.items() if data["role"] == "command")
    menu = await hass.config_entries.subentries.async_init(
        (flow_entry.entry_id, SUBENTRY_DEVICE),
        context={"source": "reconfigure", "subentry_id": next(iter(flow_entry.subentries))},
    )
    result = await step(hass, menu, {"next_step_id": "edit"})
    result = await step(hass, result, {"point": command})
    assert result["step_id"] == "composite_edit"
    result = await step(hass, result, {"address": "M1.1"})  # its own address is not taken
    assert result["step_id"] == "composite_part"
    menu = await step(hass, result, {"read_only": False})
    points = await saved(hass, flow_entry, menu)
    assert "pulse" not in points[command]
    assert points[command]["role"] == "command"
    assert len({data["entity"] for data in points.values()}) == 1


async def saved(hass: HomeAssistant, flow_entry: MockConfigEntry, menu: Any) -> dict[str, Any]:
    """Save the machine from its menu; return its stored points."""
    await step(hass, menu, {"next_step_id": "save"})
    (device,) = flow_entry.subentries.values()
    return dict(device.data[CONF_POINTS])
