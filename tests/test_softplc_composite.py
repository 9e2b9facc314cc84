"""A light of several addresses on SoftPLC (WEB.TLM): state, command and brightness, as anywhere."""

from __future__ import annotations

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.light import (  # type: ignore[attr-defined]
    ATTR_BRIGHTNESS,
    DOMAIN as LIGHT_DOMAIN,
)
from homeassistant.const import ATTR_ENTITY_ID, SERVICE_TURN_ON, STATE_ON
from homeassistant.core import HomeAssistant

from custom_components.plc_bridge.const import CONF_OPTIONS
from simulators.softplc import SoftplcSimulator
from tests.entries import point, poll
from tests.harness import make_softplc_entry

POINTS = [
    point("l1", "Hall", "light", "I:0/0", "BOOL", role="state", read_only=True),
    point("l2", "Hall", "light", "B3:0/2", "BOOL", role="command"),
    point("l3", "Hall", "light", "N7:5", "INT", role="brightness"),
]
HALL = "light.softplc_hall"


async def test_softplc_light(
    hass: HomeAssistant, softplc_ha_sim: SoftplcSimulator, freezer: FrozenDateTimeFactory
) -> None:
    """Every part in the one scattered POST; the command and brightness written together."""
    cert, key = softplc_ha_sim.client_certificate(trusted=True)
    options = {CONF_OPTIONS: {"client_certificate": cert, "client_key": key}}
    entry = make_softplc_entry(hass, softplc_ha_sim, POINTS, **options)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    state = hass.states.get(HALL)
    assert (state.state, state.attributes[ATTR_BRIGHTNESS]) == (STATE_ON, 13)
    before = softplc_ha_sim.requests
    await poll(hass, freezer)
    assert softplc_ha_sim.requests - before == 1
    await hass.services.async_call(
        LIGHT_DOMAIN, SERVICE_TURN_ON, {ATTR_ENTITY_ID: HALL, ATTR_BRIGHTNESS: 255}, blocking=True
    )
    assert softplc_ha_sim.files["B", 3].words[0] & 0b100
    assert softplc_ha_sim.files["N", 7].words[5] == 100
