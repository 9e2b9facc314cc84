"""Entities of several addresses on a Tecomat (TecoApi): a thermostat and a pump, as anywhere."""

from __future__ import annotations

from homeassistant.components.climate import DOMAIN as CLIMATE_DOMAIN
from homeassistant.components.climate.const import (
    ATTR_CURRENT_TEMPERATURE,
    ATTR_HVAC_ACTION,
    ATTR_HVAC_MODE,
    SERVICE_SET_HVAC_MODE,
    SERVICE_SET_TEMPERATURE,
)
from homeassistant.components.switch import DOMAIN as SWITCH_DOMAIN
from homeassistant.const import ATTR_ENTITY_ID, ATTR_TEMPERATURE, SERVICE_TURN_OFF, STATE_ON
from homeassistant.core import HomeAssistant

from simulators.tecomat import TecomatSimulator
from tests.entries import point
from tests.harness import make_tecomat_entry

POINTS = [
    point("t1", "Room", "climate", "Main.myObject2.value", "REAL", role="current_temperature"),
    point(
        "t2",
        "Room",
        "climate",
        "Main.myObject3.value",
        "REAL",
        role="target_temperature",
        min=10.0,
        max=30.0,
        step=0.5,
    ),
    point(
        "t3",
        "Room",
        "climate",
        "plcData.varUsint",
        "USINT",
        role="hvac_mode",
        value_map="0=off;11=heat;12=cool",
    ),
    point(
        "t4",
        "Room",
        "climate",
        "plcData.varUint",
        "UINT",
        role="hvac_action",
        value_map="0=idle;2222=heating",
        read_only=True,
    ),
    point("p1", "Pump", "switch", "plcData.varBool1", "BOOL", role="state", read_only=True),
    point("p2", "Pump", "switch", "Main.pump.value", "BOOL", role="command"),
]
ROOM = "climate.fx2_cp2080_room"


async def test_tecomat_thermostat_and_pump(
    hass: HomeAssistant, tecomat_ha_sim: TecomatSimulator
) -> None:
    """One GetObject per poll for every part; the writes go through PutObject."""
    entry = make_tecomat_entry(hass, tecomat_ha_sim, POINTS)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    state = hass.states.get(ROOM)
    assert state.state == "heat"
    assert state.attributes[ATTR_CURRENT_TEMPERATURE] == 22.1
    assert (state.attributes[ATTR_TEMPERATURE], state.attributes[ATTR_HVAC_ACTION]) == (
        23,
        "heating",
    )
    await hass.services.async_call(
        CLIMATE_DOMAIN,
        SERVICE_SET_TEMPERATURE,
        {ATTR_ENTITY_ID: ROOM, ATTR_TEMPERATURE: 21.5},
        blocking=True,
    )
    assert tecomat_ha_sim.get("Main.myObject3.value") == 21.5
    await hass.services.async_call(
        CLIMATE_DOMAIN,
        SERVICE_SET_HVAC_MODE,
        {ATTR_ENTITY_ID: ROOM, ATTR_HVAC_MODE: "cool"},
        blocking=True,
    )
    assert tecomat_ha_sim.get("plcData.varUsint") == 12
    assert hass.states.get("switch.fx2_cp2080_pump").state == STATE_ON
    await hass.services.async_call(
        SWITCH_DOMAIN,
        SERVICE_TURN_OFF,
        {ATTR_ENTITY_ID: "switch.fx2_cp2080_pump"},
        blocking=True,
    )
    assert tecomat_ha_sim.get("Main.pump.value") is False
    reads = tecomat_ha_sim.calls["GetObject"]
    await entry.runtime_data.coordinator.async_refresh()
    assert tecomat_ha_sim.calls["GetObject"] - reads == 1
