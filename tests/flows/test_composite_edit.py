"""Editing and removing the parts of an entity of several addresses from the device menu.

Editing a part opens its entity's page with every part as stored: a part's address and data
type can change (checked as a new part is), a role can be added or cleared; the entity keeps
its unique id and entity id, each kept role its point id, and reads the new address. What the
page does not ask (a part's codes, its scale) stays as stored. A bad address is refused on its
section and changes nothing. Removing parts may not leave an entity with none that shows it.
"""

from __future__ import annotations

from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.cover import ATTR_CURRENT_POSITION
from homeassistant.components.switch import DOMAIN as SWITCH_DOMAIN
from homeassistant.config_entries import SOURCE_RECONFIGURE
from homeassistant.const import ATTR_ENTITY_ID, SERVICE_TURN_OFF
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType, InvalidData
from homeassistant.helpers import entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import CONF_POINTS, SUBENTRY_DEVICE
from simulators.s7_smart import S7SmartSimulator
from simulators.tecomat import TecomatSimulator
from tests.entries import DEVICE_ID, make_entry, point, poll, read_edits
from tests.flows.forms import MACHINE, error_message, page_shown, step, strings_at
from tests.harness import make_tecomat_entry

pytestmark = pytest.mark.no_pacing

RANGE = {"raw_min": 0, "raw_max": 27648, "shown_min": 0, "shown_max": 100}
KEY = {"entity": "s0"}  # the entity's key: the id of a first part removed long ago
SHUTTER = [
    point("s1", "Shutter", "cover", "VW40", "signed", role="position", read_only=True, **RANGE),
    point("s2", "Shutter", "cover", "Q0.4", "signed", role="open", **KEY),
    point("s3", "Shutter", "cover", "Q0.5", "signed", role="close", **KEY),
    point("s4", "Shutter", "cover", "Q0.6", "signed", role="stop", pulse=1.0, **KEY),
]
SHUTTER[0][1].update(KEY)
SHUTTER[0][1]["precision"] = 0  # a setting the page does not ask
BLIND = [point("b1", "Blind", "cover", "VW60", "signed", role="position", entity="b0", **RANGE)]
SHUTTER_ID, BLIND_ID = "cover.s7_200_smart_shutter", "cover.s7_200_smart_blind"


async def set_up(hass: HomeAssistant, sim: S7SmartSimulator) -> MockConfigEntry:
    """Set up the simulator's entry with the shutter and the blind."""
    entry = make_entry(hass, sim, [*SHUTTER, *BLIND])
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    return entry


async def edit(hass: HomeAssistant, entry: MockConfigEntry, point_id: str) -> Any:
    """Open the machine's menu, choose edit and the part; return its entity's page."""
    menu = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_DEVICE),
        context={"source": SOURCE_RECONFIGURE, "subentry_id": DEVICE_ID},
    )
    result = await step(hass, menu, {"next_step_id": "edit"})
    result = await step(hass, result, {"point": point_id})
    assert result["step_id"] == "composite_entity"
    return result


def error_text(key: str) -> str:
    """Return an error's English message (one without placeholders)."""
    return str(strings_at(*MACHINE, "error", key))


def stored(entry: MockConfigEntry) -> dict[str, Any]:
    """Return the machine's stored points."""
    return dict(entry.subentries[DEVICE_ID].data[CONF_POINTS])


def registered(hass: HomeAssistant, entity_id: str) -> tuple[str, str]:
    """Return an entity's id and unique id as the registry holds them."""
    found = er.async_get(hass).async_get(entity_id)
    assert found is not None, entity_id
    return found.entity_id, found.unique_id


async def test_move_a_part(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """The shutter's position moves to another word: same entity, the new word's value."""
    s7_smart_ha_sim.set("VW40", 13824)
    s7_smart_ha_sim.set("VW48", 27648)
    entry = await set_up(hass, s7_smart_ha_sim)
    before = registered(hass, SHUTTER_ID)
    assert hass.states.get(SHUTTER_ID).attributes[ATTR_CURRENT_POSITION] == 50
    result = await edit(hass, entry, "s1")
    assert result["description_placeholders"]["title"] == "Cover: Shutter"
    page = page_shown(result)
    assert page["position"] == {
        "position": "VW40",
        "position_data_type": "signed",
        "raw_min": 0,
        "raw_max": 27648,  # the part's settings, as they were
    }
    assert page["commands"]["stop"] == "Q0.6"
    assert page["commands"]["pulse"] == 1.0
    page["position"]["position"] = " vw48 "
    menu = await step(hass, result, page)
    assert menu["type"] is FlowResultType.MENU, menu.get("errors")
    result = await step(hass, menu, {"next_step_id": "save"})
    assert result["type"] is FlowResultType.ABORT
    await read_edits(hass, freezer)
    points = stored(entry)
    assert points["s1"]["address"] == "VW48"
    assert (points["s1"]["role"], points["s1"]["entity"], points["s1"]["raw_max"]) == (
        "position",
        "s0",
        27648,
    )
    assert registered(hass, SHUTTER_ID) == before
    assert hass.states.get(SHUTTER_ID).attributes[ATTR_CURRENT_POSITION] == 100
    s7_smart_ha_sim.set("VW40", 0)  # the old word is no longer read
    s7_smart_ha_sim.set("VW48", 6912)
    await poll(hass, freezer)
    assert hass.states.get(SHUTTER_ID).attributes[ATTR_CURRENT_POSITION] == 25


async def test_a_lone_part_keeps_its_entity(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """An entity of one part whose key is not the part's own id keeps it when the part moves."""
    s7_smart_ha_sim.set("VW62", 27648)
    entry = await set_up(hass, s7_smart_ha_sim)
    before = registered(hass, BLIND_ID)
    assert before[1].endswith("_b0")
    result = await edit(hass, entry, "b1")
    page = page_shown(result)
    page["position"] = {"position": "VW62", "raw_min": 0, "raw_max": 27648}  # the first type
    menu = await step(hass, result, page)
    assert menu["type"] is FlowResultType.MENU, menu.get("errors")
    await step(hass, menu, {"next_step_id": "save"})
    await read_edits(hass, freezer)
    assert stored(entry)["b1"]["entity"] == "b0"
    assert registered(hass, BLIND_ID) == before
    assert hass.states.get(BLIND_ID).attributes[ATTR_CURRENT_POSITION] == 100


async def test_a_part_edited_in_place(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """Parts keep their own addresses (their own, not in use) while a shared setting changes
    for all of them; a cleared role goes, a new one joins with the entity's key."""
    entry = await set_up(hass, s7_smart_ha_sim)
    before = registered(hass, SHUTTER_ID)
    points = stored(entry)
    result = await edit(hass, entry, "s4")
    page = page_shown(result)
    page["commands"]["pulse"] = 2.5
    page["commands"].pop("close")
    page["limits"] = {"closed_limit": "I0.1", "closed_limit_invert": True}
    menu = await step(hass, result, page)
    assert menu["type"] is FlowResultType.MENU, menu.get("errors")
    await step(hass, menu, {"next_step_id": "save"})
    after = stored(entry)
    assert (after["s4"]["address"], after["s4"]["pulse"]) == ("Q0.6", 2.5)
    assert after["s2"]["pulse"] == 2.5  # the commands' pulse is asked once for all
    assert "s3" not in after  # the close command was cleared
    (limit,) = (data for data in after.values() if data.get("role") == "closed_limit")
    assert (limit["entity"], limit["read_only"], limit["invert"]) == ("s0", True, True)
    assert after["s1"]["precision"] == points["s1"]["precision"] == 0  # not asked: kept
    assert registered(hass, SHUTTER_ID) == before


async def test_bad_addresses_are_refused(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """The parser's refusal, an address in use and an input for a command: on the field."""
    s7_smart_ha_sim.set("VW40", 13824)
    entry = await set_up(hass, s7_smart_ha_sim)
    points = stored(entry)
    result = await edit(hass, entry, "s1")
    page = page_shown(result)

    async def refused(section_name: str, **fields: str) -> str:
        """Submit the page with these fields changed; return the section's message."""
        changed = {**page, section_name: {**page[section_name], **fields}}
        answer = await step(hass, result, changed)
        assert answer["errors"] == {section_name: f"in_{section_name}"}
        return str(answer["description_placeholders"][f"{section_name}_problem"])

    assert "VW4x" in await refused("position", position="VW4x")
    assert await refused("position", position="VW60") == error_text("already_configured")
    with pytest.raises(InvalidData):  # the S7-200 SMART's field offers its modes only
        await refused("position", position_data_type="text")
    assert (await refused("commands", open="I0.3")).startswith("I0.3 can never be written")
    data_type = {"open": "VD80", "open_data_type": "float"}
    assert "VD80 as float" in await refused("commands", **data_type)
    empty = {name: {} for name, value in page.items() if isinstance(value, dict)}
    cleared = await step(hass, result, {**page, **empty})
    assert cleared["errors"] == {"base": "role_missing"}
    assert stored(entry) == points
    await read_edits(hass, freezer)
    assert hass.states.get(SHUTTER_ID).attributes[ATTR_CURRENT_POSITION] == 50


async def test_removing_parts(hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator) -> None:
    """Parts that leave the shutter only its stop button are refused; all of them may go."""
    entry = await set_up(hass, s7_smart_ha_sim)
    menu = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_DEVICE),
        context={"source": SOURCE_RECONFIGURE, "subentry_id": DEVICE_ID},
    )
    result = await step(hass, menu, {"next_step_id": "remove"})
    result = await step(hass, result, {"point": ["s1", "s2", "s3"]})
    assert result["errors"] == {"base": "role_left_missing"}
    assert error_message(result, "base", *MACHINE).startswith("Shutter would keep none")
    menu = await step(hass, result, {"point": ["s1", "s2", "s3", "s4"]})
    assert menu["type"] is FlowResultType.MENU
    await step(hass, menu, {"next_step_id": "save"})
    assert set(stored(entry)) == {"b1"}


async def test_move_a_command_on_a_tecomat(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, tecomat_ha_sim: TecomatSimulator
) -> None:
    """On a Tecomat the pump's command moves to another public variable, checked by TecoApi's
    parser; the switch keeps its id and writes the new variable."""
    pump = [
        point("p1", "Pump", "switch", "plcData.varBool1", "BOOL", role="state", read_only=True),
        point("p2", "Pump", "switch", "Main.pump.value", "BOOL", role="command"),
    ]
    entry = make_tecomat_entry(hass, tecomat_ha_sim, pump)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    (switch,) = [
        e.entity_id
        for e in er.async_entries_for_config_entry(er.async_get(hass), entry.entry_id)
        if e.domain == SWITCH_DOMAIN
    ]
    before = registered(hass, switch)
    result = await edit(hass, entry, "p2")
    page = page_shown(result)
    page["on_off"]["command"] = "plcData.var Bool0"
    answer = await step(hass, result, page)
    assert answer["errors"] == {"on_off": "in_on_off"}
    page["on_off"]["command"] = "plcData.varBool0"
    menu = await step(hass, result, page)
    assert menu["type"] is FlowResultType.MENU, menu.get("errors")
    await step(hass, menu, {"next_step_id": "save"})
    await read_edits(hass, freezer)
    assert registered(hass, switch) == before
    tecomat_ha_sim.set("Main.pump.value", True)
    tecomat_ha_sim.set("plcData.varBool0", True)
    await hass.services.async_call(
        SWITCH_DOMAIN, SERVICE_TURN_OFF, {ATTR_ENTITY_ID: switch}, blocking=True
    )
    assert tecomat_ha_sim.get("plcData.varBool0") is False
    assert tecomat_ha_sim.get("Main.pump.value") is True  # the old variable is left alone
