"""Tests of the text platform: writable STRING points, on a Tecomat and an S7-200 SMART PLC."""

from __future__ import annotations

from homeassistant.components.text import (
    ATTR_MAX,
    ATTR_MIN,
    ATTR_MODE,
    ATTR_VALUE,
    DOMAIN as TEXT_DOMAIN,
    SERVICE_SET_VALUE,
)
from homeassistant.const import ATTR_ENTITY_ID, STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import HomeAssistantError, ServiceValidationError
from homeassistant.helpers import device_registry as dr, entity_registry as er
import pytest

from simulators.s7_smart import S7SmartSimulator
from simulators.tecomat import TecomatSimulator
from tests.entries import DEVICE_ID, make_entry, point
from tests.harness import TECOMAT_SERIAL, make_tecomat_entry

pytestmark = pytest.mark.no_pacing

GREETING = "text.fx2_cp2080_greeting"
LABEL = "text.fx2_cp2080_label"
POINTS = [
    point("greeting", "Greeting", "text", "plcData.varString", "STRING"),
    point("label", "Label", "text", "plcName", "STRING", read_only=True),
    point("sport", "Sport", "text", "myObject.favorites.sport", "STRING"),
]


async def set_text(hass: HomeAssistant, entity_id: str, value: str) -> None:
    """Call text.set_value and wait for it."""
    await hass.services.async_call(
        TEXT_DOMAIN,
        SERVICE_SET_VALUE,
        {ATTR_ENTITY_ID: entity_id, ATTR_VALUE: value},
        blocking=True,
    )
    # A poll still running defers the write's refresh (debounce): wait for it.
    await hass.async_block_till_done(wait_background_tasks=True)


@pytest.fixture
async def text_sim(hass: HomeAssistant, tecomat_ha_sim: TecomatSimulator) -> TecomatSimulator:
    """The Tecomat simulator with an entry of three text points, set up."""
    entry = make_tecomat_entry(hass, tecomat_ha_sim, POINTS)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    return tecomat_ha_sim


async def test_text_entities(
    hass: HomeAssistant,
    text_sim: TecomatSimulator,
    entity_registry: er.EntityRegistry,
    device_registry: dr.DeviceRegistry,
) -> None:
    """Each STRING point is a text entity of the PLC's device, up to 255 characters."""
    state = hass.states.get(GREETING)
    assert state is not None
    assert state.state == "Hello everybody"
    assert state.attributes[ATTR_MIN] == 0
    assert state.attributes[ATTR_MAX] == 255
    assert state.attributes[ATTR_MODE] == "text"
    assert hass.states.get(LABEL).state == "myFoxtrot"
    assert hass.states.get("text.fx2_cp2080_sport").state == "Soccer"
    registered = entity_registry.async_get(GREETING)
    assert registered is not None
    assert registered.unique_id == f"{TECOMAT_SERIAL}_greeting"
    assert registered.config_subentry_id == DEVICE_ID
    device = device_registry.async_get(registered.device_id or "")
    assert device is not None
    plc = device_registry.async_get(device.via_device_id or "")
    assert plc is not None
    assert plc.manufacturer == "Teco"
    assert plc.serial_number == TECOMAT_SERIAL


async def test_set_value(hass: HomeAssistant, text_sim: TecomatSimulator) -> None:
    """Setting a text writes the STRING; the state follows."""
    await set_text(hass, "text.fx2_cp2080_sport", "Ice hockey")
    assert text_sim.get("myObject.favorites.sport") == "Ice hockey"
    assert hass.states.get("text.fx2_cp2080_sport").state == "Ice hockey"
    assert hass.states.get(GREETING).state == "Hello everybody"


async def test_read_only_refused(hass: HomeAssistant, text_sim: TecomatSimulator) -> None:
    """A read-only text point refuses writes, translated, before anything is sent."""
    await hass.async_block_till_done(wait_background_tasks=True)
    before = text_sim.requests
    with pytest.raises(ServiceValidationError) as caught:
        await set_text(hass, LABEL, "other")
    assert caught.value.translation_key == "read_only"
    assert text_sim.requests == before
    assert text_sim.get("plcName") == "myFoxtrot"


async def test_too_long_refused_by_home_assistant(
    hass: HomeAssistant, text_sim: TecomatSimulator
) -> None:
    """Longer than the 255 characters a STRING holds: refused before the integration sees it."""
    await hass.async_block_till_done(wait_background_tasks=True)
    before = text_sim.requests
    with pytest.raises(ValueError, match="too long"):
        await set_text(hass, GREETING, "x" * 256)
    assert text_sim.requests == before


async def test_longer_than_the_variable(hass: HomeAssistant, text_sim: TecomatSimulator) -> None:
    """A text longer than the PLC variable's STRING[n]: the PLC's answer is a translated error."""
    with pytest.raises(HomeAssistantError) as caught:
        await set_text(hass, "text.fx2_cp2080_sport", "y" * 40)  # STRING[24]
    assert caught.value.translation_key == "write_failed"
    assert text_sim.get("myObject.favorites.sport") == "Soccer"


async def test_unavailable_while_its_variable_is_missing(
    hass: HomeAssistant, text_sim: TecomatSimulator
) -> None:
    """A text whose variable the PLC lost is unavailable; the others stay."""
    text_sim.rename("plcData.varString", "varText")
    await hass.config_entries.async_entries("plc_bridge")[
        0
    ].runtime_data.coordinator.async_refresh()
    await hass.async_block_till_done()
    assert hass.states.get(GREETING).state == STATE_UNAVAILABLE
    assert hass.states.get(LABEL).state == "myFoxtrot"


async def test_s7_smart_text(hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator) -> None:
    """The platform is vendor-neutral: an S7-200 SMART string in V memory."""
    entry = make_entry(hass, s7_smart_ha_sim, [point("name", "Name", "text", "VB200", "string")])
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    entity_id = "text.s7_200_smart_name"
    assert hass.states.get(entity_id).state == "Line 1"
    await set_text(hass, entity_id, "Line 2")
    assert s7_smart_ha_sim.get("VB200", "string") == "Line 2"
    assert hass.states.get(entity_id).state == "Line 2"
