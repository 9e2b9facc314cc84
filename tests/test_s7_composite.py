"""A cover of several addresses on an S7 CPU (ISO-on-TCP): DB words and bits, as anywhere."""

from __future__ import annotations

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.cover import (
    ATTR_CURRENT_POSITION,
    ATTR_POSITION,
    DOMAIN as COVER_DOMAIN,
    SERVICE_OPEN_COVER,
    SERVICE_SET_COVER_POSITION,
)
from homeassistant.const import ATTR_ENTITY_ID
from homeassistant.core import HomeAssistant

from simulators.s7 import S7Simulator
from tests.entries import point, poll
from tests.harness import make_s7_entry

RANGE = {"raw_min": 0, "raw_max": 27648, "shown_min": 0, "shown_max": 100}
POINTS = [
    point("c1", "Gate", "cover", "DB1.DBW100", "INT", role="position", read_only=True, **RANGE),
    point("c2", "Gate", "cover", "DB1.DBW102", "INT", role="set_position", **RANGE),
    point("c3", "Gate", "cover", "DB1.DBX104.0", "BOOL", role="open"),
    point("c4", "Gate", "cover", "DB1.DBX106.0", "BOOL", role="closed_limit", read_only=True),
]
GATE = "cover.s7_300_gate"


async def test_s7_gate(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, s7_ha_sim: S7Simulator
) -> None:
    """Position through the range, a bit command written bit-exact, the limit read."""
    s7_ha_sim.set_db(1, 100, (20736).to_bytes(2, "big"))
    s7_ha_sim.set_db(1, 104, b"\x80")
    entry = make_s7_entry(hass, s7_ha_sim, POINTS)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    state = hass.states.get(GATE)
    assert (state.state, state.attributes[ATTR_CURRENT_POSITION]) == ("open", 75)
    await hass.services.async_call(
        COVER_DOMAIN,
        SERVICE_SET_COVER_POSITION,
        {ATTR_ENTITY_ID: GATE, ATTR_POSITION: 10},
        blocking=True,
    )
    assert s7_ha_sim.get_db(1, 102, 2) == (2765).to_bytes(2, "big")
    await hass.services.async_call(
        COVER_DOMAIN, SERVICE_OPEN_COVER, {ATTR_ENTITY_ID: GATE}, blocking=True
    )
    assert s7_ha_sim.get_db(1, 104, 1) == b"\x81"
    s7_ha_sim.set_db(1, 106, b"\x01")
    s7_ha_sim.set_db(1, 100, b"\x00\x00")
    await poll(hass, freezer)
    assert hass.states.get(GATE).state == "closed"
