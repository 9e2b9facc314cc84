"""Tests of switches and lights with their state and command at separate addresses."""

from __future__ import annotations

from datetime import timedelta
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.light import (  # type: ignore[attr-defined]
    ATTR_BRIGHTNESS,
    DOMAIN as LIGHT_DOMAIN,
)
from homeassistant.components.switch import DOMAIN as SWITCH_DOMAIN
from homeassistant.const import (
    ATTR_ENTITY_ID,
    SERVICE_TURN_OFF,
    SERVICE_TURN_ON,
    STATE_OFF,
    STATE_ON,
)
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import HomeAssistantError
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, async_fire_time_changed

from simulators.s7_smart import S7SmartSimulator
from tests.entries import make_entry, point, poll

pytestmark = pytest.mark.no_pacing

RANGE = {"raw_min": 0, "raw_max": 27648, "shown_min": 0, "shown_max": 100}
POINTS = [
    point("plain", "Plain", "switch", "Q0.0", "signed"),
    point("p1", "Pump", "switch", "I0.3", "signed", role="state", read_only=True),
    point("p2", "Pump", "switch", "M1.0", "signed", role="command"),
    point("h1", "Hall", "switch", "Q0.3", "signed", role="state", read_only=True),
    point("h2", "Hall", "switch", "M1.1", "signed", role="command", pulse=0.5),
    point("l1", "Lamp", "light", "Q0.5", "signed", role="state", read_only=True),
    point("l2", "Lamp", "light", "M2.0", "signed", role="command", pulse=0.5),
    point("l3", "Lamp", "light", "VW60", "signed", role="brightness", **RANGE),
    point("d1", "Dimmer", "light", "VW62", "signed", role="brightness"),
]


@pytest.fixture
async def switches_and_lights(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> MockConfigEntry:
    """The simulator's entry with plain and two-address switches and lights, set up."""
    s7_smart_ha_sim.set("VW60", 13824)
    s7_smart_ha_sim.set("VW62", 40)
    entry = make_entry(hass, s7_smart_ha_sim, POINTS)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    return entry


async def act(hass: HomeAssistant, domain: str, service: str, name: str, **data: Any) -> None:
    """Call a switch or light action on an entity of the test PLC."""
    await hass.services.async_call(
        domain, service, {ATTR_ENTITY_ID: f"{domain}.s7_200_smart_{name}", **data}, blocking=True
    )


async def wait(hass: HomeAssistant, freezer: FrozenDateTimeFactory, seconds: float) -> None:
    """Let time pass and the timers due run."""
    freezer.tick(timedelta(seconds=seconds))
    async_fire_time_changed(hass)
    await hass.async_block_till_done(wait_background_tasks=True)


async def test_level_command(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    s7_smart_ha_sim: S7SmartSimulator,
    switches_and_lights: MockConfigEntry,
) -> None:
    """The state is read from one address, the command written to another; plain stays."""
    assert hass.states.get("switch.s7_200_smart_plain") is not None
    assert hass.states.get("switch.s7_200_smart_pump").state == STATE_OFF
    await act(hass, SWITCH_DOMAIN, SERVICE_TURN_ON, "pump")
    assert s7_smart_ha_sim.get("M1.0") is True
    assert s7_smart_ha_sim.get("I0.3") is False
    s7_smart_ha_sim.set("I0.3", True)
    await poll(hass, freezer)
    assert hass.states.get("switch.s7_200_smart_pump").state == STATE_ON
    await act(hass, SWITCH_DOMAIN, SERVICE_TURN_OFF, "pump")
    assert s7_smart_ha_sim.get("M1.0") is False


async def test_impulse_relay(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    s7_smart_ha_sim: S7SmartSimulator,
    switches_and_lights: MockConfigEntry,
) -> None:
    """A pulse is sent only when the state differs from the one asked for."""
    await act(hass, SWITCH_DOMAIN, SERVICE_TURN_ON, "hall")
    assert s7_smart_ha_sim.get("M1.1") is True
    await wait(hass, freezer, 0.6)
    assert s7_smart_ha_sim.get("M1.1") is False
    writes = s7_smart_ha_sim.calls["write"]
    assert writes == 2
    s7_smart_ha_sim.set("Q0.3", True)
    await poll(hass, freezer)
    await act(hass, SWITCH_DOMAIN, SERVICE_TURN_ON, "hall")
    assert s7_smart_ha_sim.calls["write"] == writes
    await act(hass, SWITCH_DOMAIN, SERVICE_TURN_OFF, "hall")
    assert s7_smart_ha_sim.get("M1.1") is True


async def test_pulse_refused_with_state_unknown(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """With the state unreadable a pulse could toggle the wrong way: nothing is sent."""
    points = [
        point("h1", "Hall", "switch", "VW30000", "signed", role="state", read_only=True),
        point("h2", "Hall", "switch", "M1.1", "signed", role="command", pulse=0.5),
    ]
    entry = make_entry(hass, s7_smart_ha_sim, points)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    with pytest.raises(HomeAssistantError) as err:
        await act(hass, SWITCH_DOMAIN, SERVICE_TURN_ON, "hall")
    assert err.value.translation_key == "state_unknown"
    assert s7_smart_ha_sim.calls["write"] == 0


async def test_dimmable_light(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    s7_smart_ha_sim: S7SmartSimulator,
    switches_and_lights: MockConfigEntry,
) -> None:
    """Brightness through the range; a pulse command toggles only a light that is off."""
    state = hass.states.get("light.s7_200_smart_lamp")
    assert state.state == STATE_OFF
    await act(hass, LIGHT_DOMAIN, SERVICE_TURN_ON, "lamp", **{ATTR_BRIGHTNESS: 255})
    assert s7_smart_ha_sim.get("VW60") == 27648
    assert s7_smart_ha_sim.get("M2.0") is True
    await wait(hass, freezer, 0.6)
    s7_smart_ha_sim.set("Q0.5", True)
    await poll(hass, freezer)
    state = hass.states.get("light.s7_200_smart_lamp")
    assert (state.state, state.attributes[ATTR_BRIGHTNESS]) == (STATE_ON, 255)
    writes = s7_smart_ha_sim.calls["write"]
    await act(hass, LIGHT_DOMAIN, SERVICE_TURN_ON, "lamp", **{ATTR_BRIGHTNESS: 51})
    assert s7_smart_ha_sim.get("VW60") == 5530
    assert s7_smart_ha_sim.calls["write"] == writes + 1


async def test_dimmer_without_command(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, switches_and_lights: MockConfigEntry
) -> None:
    """A light of a brightness alone is on above 0 %, and switches by its brightness."""
    state = hass.states.get("light.s7_200_smart_dimmer")
    assert (state.state, state.attributes[ATTR_BRIGHTNESS]) == (STATE_ON, 102)
    await act(hass, LIGHT_DOMAIN, SERVICE_TURN_OFF, "dimmer")
    assert s7_smart_ha_sim.get("VW62") == 0
    await act(hass, LIGHT_DOMAIN, SERVICE_TURN_ON, "dimmer")
    assert s7_smart_ha_sim.get("VW62") == 100
