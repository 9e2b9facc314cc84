"""An alarm word's events name the alarm: in the event type an automation's trigger and the
logbook show (`Overheat raised`), and in the event data (bit, name, change)."""

from __future__ import annotations

from homeassistant.components.automation import DOMAIN as AUTOMATION_DOMAIN
from homeassistant.components.event import ATTR_EVENT_TYPES
from homeassistant.core import HomeAssistant, ServiceCall
from homeassistant.setup import async_setup_component
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, async_mock_service

from simulators.s7_smart import S7SmartSimulator

from .ha_fixtures import make_entry, point

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
    hass: HomeAssistant, s7_smart_sim: S7SmartSimulator
) -> None:
    """The word offers a raised and a cleared event type per named bit, in the bits' order."""
    await set_up(hass, s7_smart_sim)
    assert hass.states.get(ALARMS).attributes[ATTR_EVENT_TYPES] == [
        "Overheat raised",
        "Overheat cleared",
        "Low water raised",
        "Low water cleared",
    ]


async def test_automation_triggered_by_one_alarm(
    hass: HomeAssistant, s7_smart_sim: S7SmartSimulator
) -> None:
    """An automation on `Low water raised` runs for that alarm only, with its data."""
    entry = await set_up(hass, s7_smart_sim)
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
    s7_smart_sim.set("VW70", 0b0001)  # Overheat
    await entry.runtime_data.coordinator.async_refresh()
    await hass.async_block_till_done()
    assert calls == []
    s7_smart_sim.set("VW70", 0b1001)  # and Low water
    await entry.runtime_data.coordinator.async_refresh()
    await hass.async_block_till_done()
    assert [call.data for call in calls] == [{"name": "Low water", "bit": 3, "change": "raised"}]


async def test_word_without_names(hass: HomeAssistant, s7_smart_sim: S7SmartSimulator) -> None:
    """A word whose bits have no names keeps the generic types and fires nothing."""
    point_id, data = WORD
    entry = make_entry(
        hass, s7_smart_sim, [(point_id, {k: v for k, v in data.items() if k != "bits"})]
    )
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert hass.states.get(ALARMS).attributes[ATTR_EVENT_TYPES] == ["raised", "cleared"]
