"""A fan of several addresses on PLCnext: an impulse command, speed and presets, as anywhere."""

from __future__ import annotations

from datetime import timedelta

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.fan import (  # type: ignore[attr-defined]
    ATTR_PERCENTAGE,
    ATTR_PRESET_MODE,
    DOMAIN as FAN_DOMAIN,
    SERVICE_SET_PERCENTAGE,
)
from homeassistant.const import ATTR_ENTITY_ID, SERVICE_TURN_OFF, STATE_ON
from homeassistant.core import HomeAssistant
from pytest_homeassistant_custom_component.common import async_fire_time_changed

from simulators.plcnext import PlcnextSimulator
from tests.entries import point
from tests.harness import make_plcnext_entry

MAIN = "Arp.Plc.Eclr/MainInstance."
RANGE = {"raw_min": 0, "raw_max": 250, "shown_min": 0, "shown_max": 100}
POINTS = [
    point("f1", "Vent", "fan", MAIN + "Alarm", "BOOL", role="state", read_only=True),
    point("f2", "Vent", "fan", MAIN + "Pump", "BOOL", role="command", pulse=1.0),
    point("f3", "Vent", "fan", MAIN + "Tiny", "USINT", role="percentage", **RANGE),
    point("f4", "Vent", "fan", MAIN + "Small", "SINT", role="preset", value_map="-5=Eco;5=Boost"),
]
VENT = "fan.plcnext_vent"


async def test_plcnext_fan(
    hass: HomeAssistant, plcnext_ha_sim: PlcnextSimulator, freezer: FrozenDateTimeFactory
) -> None:
    """Speed through the range, preset by label, an impulse command pulsed only to change."""
    entry = make_plcnext_entry(hass, plcnext_ha_sim, POINTS)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    state = hass.states.get(VENT)
    assert state.state == STATE_ON
    assert (state.attributes[ATTR_PERCENTAGE], state.attributes[ATTR_PRESET_MODE]) == (80, "Eco")
    await hass.services.async_call(
        FAN_DOMAIN,
        SERVICE_SET_PERCENTAGE,
        {ATTR_ENTITY_ID: VENT, ATTR_PERCENTAGE: 40},
        blocking=True,
    )
    assert plcnext_ha_sim.get("MainInstance.Tiny") == 100
    assert plcnext_ha_sim.get("MainInstance.Pump") is False
    await hass.services.async_call(
        FAN_DOMAIN, SERVICE_TURN_OFF, {ATTR_ENTITY_ID: VENT}, blocking=True
    )
    assert plcnext_ha_sim.get("MainInstance.Pump") is True
    freezer.tick(timedelta(seconds=1.1))
    async_fire_time_changed(hass)
    await hass.async_block_till_done(wait_background_tasks=True)
    assert plcnext_ha_sim.get("MainInstance.Pump") is False
