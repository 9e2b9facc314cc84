"""The entity's page as the frontend gets it: through Home Assistant's HTTP flow API.

The in-process tests submit Python values; the frontend gets the page serialized (sections as
expandable panels, every selector as its JSON) and posts the sections' values nested. A page
that cannot be serialized would show the user an error instead of a form.
"""

from __future__ import annotations

from typing import Any

from homeassistant.core import HomeAssistant
from homeassistant.setup import async_setup_component
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.plc_bridge.const import CONF_POINTS

pytestmark = pytest.mark.no_pacing

FLOWS = "/api/config/config_entries/subentries/flow"


async def test_cover_page_over_http(
    hass: HomeAssistant, hass_client: ClientSessionGenerator, flow_entry: MockConfigEntry
) -> None:
    """The kinds' menu and the cover's page serialize; nested values post back; the cover is
    stored."""
    assert await async_setup_component(hass, "config", {})
    client = await hass_client()

    async def post(path: str, body: dict[str, Any]) -> dict[str, Any]:
        """Post as the frontend does; return the flow's answer."""
        response = await client.post(path, json=body)
        assert response.status == 200, await response.text()
        answer: dict[str, Any] = await response.json()
        return answer

    flow = await post(FLOWS, {"handler": [flow_entry.entry_id, "device"]})
    step = f"{FLOWS}/{flow['flow_id']}"
    menu = await post(step, {"name": "Garage"})
    kinds = await post(step, {"next_step_id": "composite"})
    assert kinds["type"] == "menu"
    assert "entity_cover" in kinds["menu_options"]
    page = await post(step, {"next_step_id": "entity_cover"})
    assert page["step_id"] == "composite_entity"
    shown = {field["name"]: field for field in page["data_schema"]}
    assert shown["commands"]["type"] == "expandable"
    assert shown["commands"]["expanded"] is True
    assert shown["tilt"]["expanded"] is False
    inner = {field["name"]: field for field in shown["limits"]["schema"]}
    assert "select" in inner["open_limit_data_type"]["selector"]
    assert "boolean" in inner["closed_limit_invert"]["selector"]
    assert shown["device_class"]["selector"]["select"]["translation_key"] == "cover_device_class"
    values = {
        "name": "Shutter",
        "device_class": "shutter",
        "commands": {"open": "Q0.4", "close": "Q0.5"},
        "limits": {"open_limit": "I0.1", "closed_limit": "I0.2", "closed_limit_invert": True},
        "position": {},
        "tilt": {},
        "entity_options": {"poll": "normal"},
    }
    refused = await post(step, {**values, "commands": {"open": "IW0"}})
    assert refused["errors"] == {"commands": "in_commands"}
    assert refused["description_placeholders"]["commands_role"] == "Open command"
    refused = await post(step, {**values, "position": {"position": "VW40", "raw_min": 0}})
    assert refused["errors"] == {"position": "in_position"}
    refused_shown = {field["name"]: field for field in refused["data_schema"]}
    assert refused_shown["position"]["expanded"] is True  # folded until it holds the error
    menu = await post(step, values)
    assert menu["type"] == "menu", menu
    saved = await post(step, {"next_step_id": "save"})
    assert saved["type"] == "create_entry"
    (device,) = flow_entry.subentries.values()
    roles = {data["role"] for data in device.data[CONF_POINTS].values()}
    assert roles == {"open", "close", "open_limit", "closed_limit"}
