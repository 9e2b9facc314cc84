"""A SoftPLC end to end: set up, polled in one POST, written with a client certificate."""

from __future__ import annotations

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.number import ATTR_VALUE, DOMAIN as NUMBER_DOMAIN, SERVICE_SET_VALUE
from homeassistant.components.switch import DOMAIN as SWITCH_DOMAIN
from homeassistant.config_entries import SOURCE_REAUTH, ConfigEntryState
from homeassistant.const import ATTR_ENTITY_ID, SERVICE_TURN_ON, STATE_OFF, STATE_ON
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import HomeAssistantError
import pytest

from custom_components.plc_bridge.const import CONF_OPTIONS
from simulators.softplc import SoftplcSimulator
from tests.entries import poll
from tests.harness import make_softplc_entry

SWITCH = "switch.softplc_lamp"
NUMBER = "number.softplc_preset"


def certificate(sim: SoftplcSimulator, *, trusted: bool = True) -> dict[str, str]:
    """Return the vendor options of a client certificate."""
    cert, key = sim.client_certificate(trusted=trusted)
    return {"client_certificate": cert, "client_key": key}


async def test_poll_and_write(
    hass: HomeAssistant, softplc_ha_sim: SoftplcSimulator, freezer: FrozenDateTimeFactory
) -> None:
    """Every point shows the simulator's value, each poll is one POST, writes land."""
    entry = make_softplc_entry(hass, softplc_ha_sim, **{CONF_OPTIONS: certificate(softplc_ha_sim)})
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert entry.state is ConfigEntryState.LOADED
    states = {s.entity_id: s.state for s in hass.states.async_all()}
    assert states["sensor.softplc_temperature"] == "21.5"
    assert states["sensor.softplc_count"] == "5"
    assert states[NUMBER] == "4000"
    assert states[SWITCH] == STATE_OFF
    assert states["binary_sensor.softplc_input"] == STATE_ON
    assert states["sensor.softplc_important"] == "10"
    before = softplc_ha_sim.requests
    await poll(hass, freezer)
    assert softplc_ha_sim.requests - before == 1
    await hass.services.async_call(
        SWITCH_DOMAIN, SERVICE_TURN_ON, {ATTR_ENTITY_ID: SWITCH}, blocking=True
    )
    await hass.services.async_call(
        NUMBER_DOMAIN, SERVICE_SET_VALUE, {ATTR_ENTITY_ID: NUMBER, ATTR_VALUE: 2500}, blocking=True
    )
    await hass.async_block_till_done(wait_background_tasks=True)
    assert softplc_ha_sim.files["B", 3].words[0] & 0b100
    assert softplc_ha_sim.files["T", 4].words[1] == 2500
    assert hass.states.get(SWITCH).state == STATE_ON  # type: ignore[union-attr]
    assert hass.states.get(NUMBER).state == "2500"  # type: ignore[union-attr]


async def test_refused_certificate_starts_reauth(
    hass: HomeAssistant, softplc_ha_sim: SoftplcSimulator
) -> None:
    """Reads work without a trusted certificate; a refused write asks for a new certificate."""
    entry = make_softplc_entry(
        hass, softplc_ha_sim, **{CONF_OPTIONS: certificate(softplc_ha_sim, trusted=False)}
    )
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert hass.states.get(SWITCH).state == STATE_OFF  # type: ignore[union-attr]
    with pytest.raises(HomeAssistantError):
        await hass.services.async_call(
            SWITCH_DOMAIN, SERVICE_TURN_ON, {ATTR_ENTITY_ID: SWITCH}, blocking=True
        )
    await hass.async_block_till_done()
    flows = hass.config_entries.flow.async_progress_by_handler("plc_bridge")
    reauth = [flow for flow in flows if flow["context"]["source"] == SOURCE_REAUTH]
    assert reauth
    assert reauth[0]["step_id"] == "reauth_softplc"
    result = await hass.config_entries.flow.async_configure(
        reauth[0]["flow_id"], certificate(softplc_ha_sim)
    )
    assert result["type"] == "abort"
    assert result["reason"] == "reauth_successful"
    await hass.async_block_till_done()
    await hass.services.async_call(
        SWITCH_DOMAIN, SERVICE_TURN_ON, {ATTR_ENTITY_ID: SWITCH}, blocking=True
    )
    assert softplc_ha_sim.files["B", 3].words[0] & 0b100
