"""Every PLC family through the one harness: what the PLC holds is shown, what is set lands.

Each of the six families (`every_plc`) is set up with a number and a switch at the addresses
its harness names; a value the PLC's program sets shows after a poll, one set in Home Assistant
lands at the simulator, and a poll costs requests at the simulator the harness counts.
"""

from __future__ import annotations

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.number import ATTR_VALUE, SERVICE_SET_VALUE
from homeassistant.const import ATTR_ENTITY_ID, SERVICE_TURN_OFF, STATE_ON
from homeassistant.core import HomeAssistant
import pytest

from tests.entries import point, poll
from tests.harness import PlcUnderTest

pytestmark = pytest.mark.no_pacing


async def test_shown_and_written(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, every_plc: PlcUnderTest
) -> None:
    """A whole number and a bit: read after setup and after a poll, written from Home Assistant."""
    plc = every_plc
    (number, number_type), (bit, bit_type) = plc.family.burst[0], plc.family.flag
    plc.write(number, 12, number_type)
    plc.write(bit, True, bit_type)
    await plc.set_up(
        hass,
        [
            point("level", "Level", "number", number, number_type, min=0.0, max=1000.0, step=1.0),
            point("lamp", "Lamp", "switch", bit, bit_type),
        ],
    )
    level, lamp = plc.entity("number", "level"), plc.entity("switch", "lamp")
    assert float(hass.states.get(level).state) == 12
    assert hass.states.get(lamp).state == STATE_ON

    requests = plc.requests()
    plc.write(number, 56, number_type)
    await poll(hass, freezer)
    assert float(hass.states.get(level).state) == 56
    assert plc.requests() > requests

    await hass.services.async_call(
        "number", SERVICE_SET_VALUE, {ATTR_ENTITY_ID: level, ATTR_VALUE: 34}, blocking=True
    )
    await hass.services.async_call(
        "switch", SERVICE_TURN_OFF, {ATTR_ENTITY_ID: lamp}, blocking=True
    )
    assert plc.read(number, number_type) == 34
    assert plc.read(bit, bit_type) in (False, 0)
