"""A machine's points as its menu and pickers list them: entity, kind, role in words, address and
the data type's label (a bit named a bit, whatever mode reads it), never a raw key."""

from __future__ import annotations

from homeassistant.config_entries import SOURCE_RECONFIGURE
from homeassistant.core import HomeAssistant
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import SUBENTRY_DEVICE
from custom_components.plc_bridge.flows.flow_lists import LISTING
from custom_components.plc_bridge.model.kinds import KINDS_IN_ORDER
from simulators.s7_smart import S7SmartSimulator
from tests.entries import DEVICE_ID, POINTS, make_entry
from tests.flows.forms import step, strings_at
from tests.test_cover import SHUTTER

pytestmark = pytest.mark.no_pacing


async def menu(hass: HomeAssistant, entry: MockConfigEntry) -> dict[str, str]:
    """Open the machine's menu; return it."""
    return await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_DEVICE),
        context={"source": SOURCE_RECONFIGURE, "subentry_id": DEVICE_ID},
    )


async def test_parts_listed_by_entity_kind_and_role(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """The menu and the edit picker say which entity, which part and which type each point is."""
    entry = make_entry(hass, s7_smart_ha_sim, [*SHUTTER, *POINTS[:2]])
    result = await menu(hass, entry)
    lines = result["description_placeholders"]["points"].splitlines()
    assert lines == [
        "- Pressure (sensor): VW10 (Signed integer)",
        "- Shutter (cover) – open limit switch: I0.1 (bit)",
        "- Shutter (cover) – closed limit switch: I0.2 (bit)",
        "- Shutter (cover) – open command: Q0.4 (bit)",
        "- Shutter (cover) – close command: Q0.5 (bit)",
        "- … (+4)",
    ]
    result = await step(hass, result, {"next_step_id": "edit"})
    (selector,) = result["data_schema"].schema.values()
    labels = {option["value"]: option["label"] for option in selector.config["options"]}
    assert labels["s1"] == "Shutter (cover) – position read: VW40 (Signed integer)"
    assert labels["temperature"] == "Temperature (sensor): VD100 (Floating point (REAL))"


def test_every_role_has_words() -> None:
    """Each role of each kind, and a bit, are named in words for the lists."""
    words = strings_at("selector", LISTING, "options")
    assert {role.key for kind in KINDS_IN_ORDER for role in kind.roles} | {"bit"} <= set(words)
    assert all(text == text.strip() and text for text in words.values())
