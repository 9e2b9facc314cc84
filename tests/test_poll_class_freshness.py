"""Poll classes never show a value older than what the link or the machine says is valid."""

from __future__ import annotations

from freezegun.api import FrozenDateTimeFactory
from homeassistant.const import STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant

from custom_components.plc_bridge.plc import Point
from simulators.s7_smart import S7SmartSimulator

from .ha_fixtures import make_entry, point
from .test_poll_classes import reads, set_up_classes, tick

__all__ = ["reads"]  # the fixture, used by name

SLOW = Point("VW2", "signed")


async def test_a_recovered_link_reads_every_class(
    hass: HomeAssistant,
    s7_smart_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    reads: list[list[Point]],
) -> None:
    """After failed polls the first good one reads the slow points too: no pre-outage value."""
    points = [
        point("fast", "Fast", "sensor", "VW0", "signed", poll="fast"),
        point("outdoor", "Outdoor", "sensor", "VW2", "signed", poll="slow"),
    ]
    s7_smart_sim.set("VW2", 5)
    entry = make_entry(hass, s7_smart_sim, points)
    await set_up_classes(hass, freezer, entry)
    await tick(hass, freezer, 3)
    assert hass.states.get("sensor.s7_200_smart_outdoor").state == "5"
    await s7_smart_sim.stop()
    await tick(hass, freezer, 2)
    assert hass.states.get("sensor.s7_200_smart_outdoor").state == STATE_UNAVAILABLE
    s7_smart_sim.set("VW2", 6)  # the PLC restarted meanwhile with another value
    await s7_smart_sim.start(s7_smart_sim.host, s7_smart_sim.port)
    count = len(reads)
    await tick(hass, freezer, 3)
    assert SLOW in reads[count]
    assert hass.states.get("sensor.s7_200_smart_outdoor").state == "6"
    assert all(SLOW not in polled for polled in reads[count + 1 :])  # then at its own pace
