"""An alarm word's events name the alarm: in the event type an automation's trigger shows
(`Overheat raised`), in the event data (bit, name, change), and in the logbook, which describes
the `plc_bridge_alarm` bus event fired with each change (the frontend's logbook line of an event
entity itself says only "detected an event")."""

from __future__ import annotations

from typing import Any

from homeassistant.components.automation import DOMAIN as AUTOMATION_DOMAIN
from homeassistant.components.event import ATTR_EVENT_TYPES
from homeassistant.const import ATTR_ENTITY_ID
from homeassistant.core import HomeAssistant, ServiceCall
from homeassistant.setup import async_setup_component
import pytest
from pytest_homeassistant_custom_component.common import (
    MockConfigEntry,
    async_capture_events,
    async_mock_service,
)

from custom_components.plc_bridge import logbook
from custom_components.plc_bridge.const import DOMAIN, EVENT_ALARM
from simulators.s7_smart import S7SmartSimulator
from tests.entries import make_entry, point

pytestmark = pytest.mark.no_pacing

ALARMS = "event.s7_200_smart_alarms"
WORD = point("alarms", "Alarms", "event", "VW70", "signed", bits="0=Overheat;3=Low water")


async def set_up(hass: HomeAssistant, sim: S7SmartSimulator) -> MockConfigEntry:
    """Set up the simulator's entry with the alarm word."""
    entry = make_entry(hass, sim, [WORD])
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    return entry


async def test_event_types_name_the_alarms(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """The word offers a raised and a cleared event type per named bit, in the bits' order."""
    await set_up(hass, s7_smart_ha_sim)
    assert hass.states.get(ALARMS).attributes[ATTR_EVENT_TYPES] == [
        "Overheat raised",
        "Overheat cleared",
        "Low water raised",
        "Low water cleared",
    ]


async def test_automation_triggered_by_one_alarm(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """An automation on `Low water raised` runs for that alarm only, with its data."""
    entry = await set_up(hass, s7_smart_ha_sim)
    calls: list[ServiceCall] = async_mock_service(hass, "test", "alarm")
    assert await async_setup_component(
        hass,
        AUTOMATION_DOMAIN,
        {
            AUTOMATION_DOMAIN: {
                "triggers": {
                    "trigger": "state",
                    "entity_id": ALARMS,
                    "attribute": "event_type",
                    "to": "Low water raised",
                },
                "actions": {
                    "action": "test.alarm",
                    "data": {
                        "name": "{{ trigger.to_state.attributes.name }}",
                        "bit": "{{ trigger.to_state.attributes.bit }}",
                        "change": "{{ trigger.to_state.attributes.change }}",
                    },
                },
            }
        },
    )
    s7_smart_ha_sim.set("VW70", 0b0001)  # Overheat
    await entry.runtime_data.coordinator.async_refresh()
    await hass.async_block_till_done()
    assert calls == []
    s7_smart_ha_sim.set("VW70", 0b1001)  # and Low water
    await entry.runtime_data.coordinator.async_refresh()
    await hass.async_block_till_done()
    assert [call.data for call in calls] == [{"name": "Low water", "bit": 3, "change": "raised"}]


async def test_word_without_names(hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator) -> None:
    """A word whose bits have no names keeps the generic types and fires nothing."""
    point_id, data = WORD
    entry = make_entry(
        hass, s7_smart_ha_sim, [(point_id, {k: v for k, v in data.items() if k != "bits"})]
    )
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert hass.states.get(ALARMS).attributes[ATTR_EVENT_TYPES] == ["raised", "cleared"]


async def test_logbook_names_the_alarm(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """Each change is fired on the bus; the logbook writes it as the alarm's name and change,
    on the alarm word's entity, in Home Assistant's language."""
    entry = await set_up(hass, s7_smart_ha_sim)
    fired = async_capture_events(hass, EVENT_ALARM)
    s7_smart_ha_sim.set("VW70", 0b1000)  # Low water
    await entry.runtime_data.coordinator.async_refresh()
    s7_smart_ha_sim.set("VW70", 0b0000)
    await entry.runtime_data.coordinator.async_refresh()
    await hass.async_block_till_done()
    assert [event.data for event in fired] == [
        {ATTR_ENTITY_ID: ALARMS, "bit": 3, "name": "Low water", "change": "raised"},
        {ATTR_ENTITY_ID: ALARMS, "bit": 3, "name": "Low water", "change": "cleared"},
    ]
    described: dict[tuple[str, str], Any] = {}
    logbook.async_describe_events(
        hass,
        lambda domain, event_type, describe: described.update({(domain, event_type): describe}),
    )
    describe = described[(DOMAIN, EVENT_ALARM)]
    assert [describe(event) for event in fired] == [
        {"name": "Low water", "message": "Raised", "entity_id": ALARMS},
        {"name": "Low water", "message": "Cleared", "entity_id": ALARMS},
    ]
