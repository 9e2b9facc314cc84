"""Selects, alarm words and pulse buttons on a Tecomat (TecoApi): the same entities as anywhere."""

from __future__ import annotations

from datetime import timedelta

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.button import DOMAIN as BUTTON_DOMAIN, SERVICE_PRESS
from homeassistant.components.select import DOMAIN as SELECT_DOMAIN, SERVICE_SELECT_OPTION
from homeassistant.const import ATTR_ENTITY_ID, ATTR_OPTION, STATE_OFF, STATE_ON
from homeassistant.core import HomeAssistant
from pytest_homeassistant_custom_component.common import async_fire_time_changed

from simulators.tecomat import TecomatSimulator
from tests.entries import point
from tests.harness import make_tecomat_entry

POINTS = [
    point("mode", "Mode", "select", "plcData.varUsint", "USINT", value_map="0=Off;11=Auto;12=Hand"),
    point("alarms", "Alarms", "event", "plcData.varWord", "WORD", bits="1=Overheat;2=Low water"),
    point("start", "Start", "button", "plcData.varBool0", "BOOL", pulse=1.0),
]


async def test_tecomat_machines(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, tecomat_ha_sim: TecomatSimulator
) -> None:
    """Shown from one GetObject per poll; the select and the pulse write through PutObject."""
    entry = make_tecomat_entry(hass, tecomat_ha_sim, POINTS)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert hass.states.get("select.fx2_cp2080_mode").state == "Auto"
    assert hass.states.get("binary_sensor.fx2_cp2080_overheat").state == STATE_ON  # 0x2222
    assert hass.states.get("binary_sensor.fx2_cp2080_low_water").state == STATE_OFF

    await hass.services.async_call(
        SELECT_DOMAIN,
        SERVICE_SELECT_OPTION,
        {ATTR_ENTITY_ID: "select.fx2_cp2080_mode", ATTR_OPTION: "Hand"},
        blocking=True,
    )
    assert tecomat_ha_sim.get("plcData.varUsint") == 12

    await hass.services.async_call(
        BUTTON_DOMAIN, SERVICE_PRESS, {ATTR_ENTITY_ID: "button.fx2_cp2080_start"}, blocking=True
    )
    assert tecomat_ha_sim.get("plcData.varBool0") is True
    freezer.tick(timedelta(seconds=1.5))
    async_fire_time_changed(hass)
    await hass.async_block_till_done(wait_background_tasks=True)
    assert tecomat_ha_sim.get("plcData.varBool0") is False

    reads = tecomat_ha_sim.calls["GetObject"]
    await entry.runtime_data.coordinator.async_refresh()
    assert tecomat_ha_sim.calls["GetObject"] - reads == 1
