"""S7 entities on a simulated CPU: DB and M points live; writes land bit- and word-exact."""

from __future__ import annotations

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.number import ATTR_VALUE, SERVICE_SET_VALUE
from homeassistant.const import (
    ATTR_ENTITY_ID,
    SERVICE_TURN_OFF,
    SERVICE_TURN_ON,
    STATE_OFF,
    STATE_ON,
)
from homeassistant.core import HomeAssistant
from homeassistant.helpers import device_registry as dr
from pytest_homeassistant_custom_component.common import MockConfigEntry

from simulators.s7 import S7Simulator
from tests.entries import poll

TEMPERATURE = "sensor.s7_300_temperature"
LEVEL = "sensor.s7_300_level"
COUNTER = "sensor.s7_300_counter"
DOOR = "binary_sensor.s7_300_door"
PUMP = "switch.s7_300_pump"
SETPOINT = "number.s7_300_setpoint"


async def test_live_values(
    hass: HomeAssistant,
    s7_ha_sim: S7Simulator,
    s7_setup: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Every platform shows the CPU's value; a change in the CPU shows after the next poll."""
    assert hass.states.get(TEMPERATURE).state == "21.5"
    assert hass.states.get(TEMPERATURE).attributes["unit_of_measurement"] == "°C"
    assert hass.states.get(LEVEL).state == "1234"
    assert hass.states.get(COUNTER).state == "-7"
    assert hass.states.get(DOOR).state == STATE_ON
    assert hass.states.get(PUMP).state == STATE_OFF
    setpoint = hass.states.get(SETPOINT)
    assert setpoint.state == "40"
    assert (setpoint.attributes["min"], setpoint.attributes["max"]) == (0, 100)

    s7_ha_sim.set_db(1, 0, b"\x00")
    s7_ha_sim.set_db(1, 2, (-300).to_bytes(2, "big", signed=True))
    s7_ha_sim.set_db(1, 8, bytes.fromhex("c0200000"))  # -2.5
    s7_ha_sim.set_bytes("M", 10, b"\x02")
    await poll(hass, freezer)
    assert hass.states.get(DOOR).state == STATE_OFF
    assert hass.states.get(LEVEL).state == "-300"
    assert hass.states.get(TEMPERATURE).state == "-2.5"
    assert hass.states.get(PUMP).state == STATE_ON


async def test_device_from_szl(
    hass: HomeAssistant, device_registry: dr.DeviceRegistry, s7_setup: MockConfigEntry
) -> None:
    """The device carries what the CPU's SZL says: type, serial, firmware."""
    (device,) = [
        device
        for device in dr.async_entries_for_config_entry(device_registry, s7_setup.entry_id)
        if device.via_device_id is None  # the PLC's own; its points' devices hang off it
    ]
    assert device.model == "CPU 315-2 PN/DP"
    assert device.serial_number == S7Simulator.serial
    assert device.sw_version is not None
    assert "3.2.6" in device.sw_version


async def test_switch_sets_only_its_bit(
    hass: HomeAssistant,
    s7_ha_sim: S7Simulator,
    s7_setup: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """turn_on sets M10.1 alone: the other bits of MB10 and the bytes around stay."""
    s7_ha_sim.set_bytes("M", 9, b"\xaa\x81\x55")
    writes = s7_ha_sim.calls["write"]
    await hass.services.async_call("switch", SERVICE_TURN_ON, {ATTR_ENTITY_ID: PUMP}, blocking=True)
    assert s7_ha_sim.calls["write"] - writes == 1
    assert s7_ha_sim.get_bytes("M", 9, 3) == b"\xaa\x83\x55"
    assert hass.states.get(PUMP).state == STATE_ON  # refreshed after the write

    await hass.services.async_call(
        "switch", SERVICE_TURN_OFF, {ATTR_ENTITY_ID: PUMP}, blocking=True
    )
    assert s7_ha_sim.get_bytes("M", 9, 3) == b"\xaa\x81\x55"
    await poll(hass, freezer)  # the refresh a write requests is debounced: the next poll
    assert hass.states.get(PUMP).state == STATE_OFF


async def test_number_writes_the_word(
    hass: HomeAssistant, s7_ha_sim: S7Simulator, s7_setup: MockConfigEntry
) -> None:
    """set_value writes DB1.DBW4 as an INT, big-endian, and nothing beside it."""
    s7_ha_sim.set_db(1, 3, b"\x11")
    s7_ha_sim.set_db(1, 6, b"\x22")
    await hass.services.async_call(
        "number", SERVICE_SET_VALUE, {ATTR_ENTITY_ID: SETPOINT, ATTR_VALUE: 73}, blocking=True
    )
    assert s7_ha_sim.get_db(1, 3, 4) == b"\x11\x00\x49\x22"
    assert hass.states.get(SETPOINT).state == "73"
