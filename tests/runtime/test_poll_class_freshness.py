"""Poll classes never show a value older than what the link or the machine says is valid."""

from __future__ import annotations

from freezegun.api import FrozenDateTimeFactory
from homeassistant.const import (
    ATTR_ENTITY_ID,
    SERVICE_TURN_ON,
    STATE_OFF,
    STATE_ON,
    STATE_UNAVAILABLE,
)
from homeassistant.core import HomeAssistant
import pytest

from custom_components.plc_bridge.model.availability import (
    CONF_AVAILABILITY_ADDRESS,
    CONF_AVAILABILITY_DATA_TYPE,
)
from custom_components.plc_bridge.plc import Point
from simulators.s7_smart import S7SmartSimulator
from tests.entries import add_entry, device, make_entry, point, sim_data
from tests.runtime.test_poll_classes import reads, set_up_classes, tick

pytestmark = pytest.mark.no_pacing

__all__ = ["reads"]  # the fixture, used by name

SLOW = Point("VW2", "signed")


async def test_a_recovered_link_reads_every_class(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    reads: list[list[Point]],
) -> None:
    """After failed polls the first good one reads the slow points too: no pre-outage value."""
    points = [
        point("fast", "Fast", "sensor", "VW0", "signed", poll="fast"),
        point("outdoor", "Outdoor", "sensor", "VW2", "signed", poll="slow"),
    ]
    s7_smart_ha_sim.set("VW2", 5)
    entry = make_entry(hass, s7_smart_ha_sim, points)
    await set_up_classes(hass, freezer, entry)
    await tick(hass, freezer, 3)
    assert hass.states.get("sensor.s7_200_smart_outdoor").state == "5"
    await s7_smart_ha_sim.stop()
    await tick(hass, freezer, 2)
    assert hass.states.get("sensor.s7_200_smart_outdoor").state == STATE_UNAVAILABLE
    s7_smart_ha_sim.set("VW2", 6)  # the PLC restarted meanwhile with another value
    await s7_smart_ha_sim.start(s7_smart_ha_sim.host, s7_smart_ha_sim.port)
    count = len(reads)
    await tick(hass, freezer, 3)
    assert SLOW in reads[count]
    assert hass.states.get("sensor.s7_200_smart_outdoor").state == "6"
    assert all(SLOW not in polled for polled in reads[count + 1 :])  # then at its own pace


async def test_a_machine_valid_again_shows_values_read_with_its_bit(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    reads: list[list[Point]],
) -> None:
    """The slow points of a machine whose data turns valid are read in the poll that says so."""
    boiler = device(
        [
            point("fast", "Fast", "sensor", "VW0", "signed", poll="fast"),
            point("outdoor", "Outdoor", "sensor", "VW2", "signed", poll="slow"),
        ],
        subentry_id="boiler",
        title="Boiler",
    )
    boiler["data"] = {
        **boiler["data"],
        CONF_AVAILABILITY_ADDRESS: "M0.0",
        CONF_AVAILABILITY_DATA_TYPE: "signed",
    }
    s7_smart_ha_sim.set("M0.0", 1)
    s7_smart_ha_sim.set("VW2", 5)
    entry = add_entry(
        hass,
        title="S7-200 SMART",
        entry_id="01JPLCBR1DGE0000000000FRSH",
        unique_id="plc-bridge-fresh",
        data=sim_data(s7_smart_ha_sim),
        subentries=[boiler],
    )
    await set_up_classes(hass, freezer, entry)
    await tick(hass, freezer, 3)
    assert hass.states.get("sensor.boiler_outdoor").state == "5"
    s7_smart_ha_sim.set("M0.0", 0)  # the remote station drops out: its inputs read 0
    s7_smart_ha_sim.set("VW2", 0)
    await tick(hass, freezer, 2)
    assert hass.states.get("sensor.boiler_outdoor").state == STATE_UNAVAILABLE
    s7_smart_ha_sim.set("M0.0", 1)
    s7_smart_ha_sim.set("VW2", 7)
    await tick(hass, freezer, 1)
    assert hass.states.get("sensor.boiler_outdoor").state == "7"
    count = len(reads)
    await tick(hass, freezer, 3)
    assert all(SLOW not in polled for polled in reads[count:])  # then at its own pace


async def test_a_data_valid_address_shown_slow_is_read_at_every_poll(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, freezer: FrozenDateTimeFactory
) -> None:
    """A machine's data-valid bit is read at every poll, though a slow point of it shows it."""
    boiler = device(
        [
            point("fast", "Fast", "sensor", "VW0", "signed", poll="fast"),
            point("link", "Station", "binary_sensor", "M0.0", "signed", poll="slow"),
        ],
        subentry_id="boiler",
        title="Boiler",
    )
    boiler["data"] = {
        **boiler["data"],
        CONF_AVAILABILITY_ADDRESS: "M0.0",
        CONF_AVAILABILITY_DATA_TYPE: "signed",
    }
    s7_smart_ha_sim.set("M0.0", 1)
    entry = add_entry(
        hass,
        title="S7-200 SMART",
        entry_id="01JPLCBR1DGE0000000000FRSH",
        unique_id="plc-bridge-fresh",
        data=sim_data(s7_smart_ha_sim),
        subentries=[boiler],
    )
    await set_up_classes(hass, freezer, entry)
    await tick(hass, freezer, 3)
    assert hass.states.get("sensor.boiler_fast").state == "0"
    s7_smart_ha_sim.set("M0.0", 0)
    await tick(hass, freezer, 1)
    assert hass.states.get("sensor.boiler_fast").state == STATE_UNAVAILABLE


async def test_a_written_part_reads_back_its_whole_entity(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    reads: list[list[Point]],
) -> None:
    """A slow switch's command written: the refresh reads its state part too, not in 60 s."""
    points = [
        point("fast", "Fast", "sensor", "VW0", "signed", poll="fast"),
        point("p1", "Burner", "switch", "I0.3", "signed", role="state", poll="slow"),
        point("p2", "Burner", "switch", "M1.0", "signed", role="command", poll="slow"),
    ]
    entry = make_entry(hass, s7_smart_ha_sim, points)
    await set_up_classes(hass, freezer, entry)
    await tick(hass, freezer, 3)
    assert hass.states.get("switch.s7_200_smart_burner").state == STATE_OFF
    s7_smart_ha_sim.set("I0.3", 1)  # the PLC follows the command
    await hass.services.async_call(
        "switch", SERVICE_TURN_ON, {ATTR_ENTITY_ID: "switch.s7_200_smart_burner"}, blocking=True
    )
    await hass.async_block_till_done()
    assert Point("I0.3", "signed") in reads[-1]
    assert hass.states.get("switch.s7_200_smart_burner").state == STATE_ON
