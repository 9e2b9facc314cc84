"""An entity named as its machine is the machine's main feature: named after the device alone."""

from __future__ import annotations

from homeassistant.components.button import DOMAIN as BUTTON_DOMAIN, SERVICE_PRESS
from homeassistant.const import ATTR_ENTITY_ID, ATTR_FRIENDLY_NAME
from homeassistant.core import HomeAssistant
import pytest

from simulators.s7_smart import S7SmartSimulator
from tests.entries import add_entry, device, point, sim_data

pytestmark = pytest.mark.no_pacing

PUMP = [
    point("p1", "Pump", "switch", "I0.3", "signed", role="state", read_only=True),
    point("p2", "Pump", "switch", "M1.0", "signed", role="command"),
    point("speed", "Speed", "sensor", "VW6", "signed"),
]
START = [point("start", "start", "button", "M2.0", "signed", pulse=0.5)]


async def test_named_as_the_machine(hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator) -> None:
    """A switch "Pump" of the machine "Pump" is `switch.pump`, "Pump"; the others keep names."""
    s7_smart_ha_sim.set("VW6", 7)
    entry = add_entry(
        hass,
        title="S7-200 SMART",
        entry_id="01JPLCBR1DGE0000000000NAME",
        unique_id="plc-bridge-names",
        data=sim_data(s7_smart_ha_sim),
        subentries=[
            device(PUMP, subentry_id="pump", title="Pump"),
            device(START, subentry_id="start", title="Start"),
        ],
    )
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert hass.states.get("switch.pump").attributes[ATTR_FRIENDLY_NAME] == "Pump"
    assert hass.states.get("sensor.pump_speed").attributes[ATTR_FRIENDLY_NAME] == "Pump Speed"
    # A button named as its machine, whatever the case: its pulse still names it in the log.
    assert hass.states.get("button.start").attributes[ATTR_FRIENDLY_NAME] == "Start"
    await hass.services.async_call(
        BUTTON_DOMAIN, SERVICE_PRESS, {ATTR_ENTITY_ID: "button.start"}, blocking=True
    )
    assert s7_smart_ha_sim.get("M2.0") == 1
