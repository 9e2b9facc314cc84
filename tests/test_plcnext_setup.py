"""A PLCnext Control end to end: live values, renewals mid-polling, writes."""

from __future__ import annotations

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.switch import DOMAIN as SWITCH_DOMAIN, SERVICE_TURN_ON
from homeassistant.config_entries import ConfigEntryState
from homeassistant.const import ATTR_ENTITY_ID, STATE_OFF, STATE_ON, STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from pytest_homeassistant_custom_component.common import MockConfigEntry

from simulators.plcnext import PlcnextSimulator
from tests.ha_fixtures import call, poll

TEMPERATURE = "sensor.plcnext_temperature"


async def test_live_values(hass: HomeAssistant, plcnext_entry: MockConfigEntry) -> None:
    """Every point shows the simulator's value; the entry is loaded."""
    assert plcnext_entry.state is ConfigEntryState.LOADED
    assert hass.states.get(TEMPERATURE).state == "21.5"
    assert hass.states.get("number.plcnext_setpoint").state == "22.0"
    assert hass.states.get("switch.plcnext_pump").state == STATE_OFF
    assert hass.states.get("binary_sensor.plcnext_alarm").state == STATE_ON
    assert hass.states.get("sensor.plcnext_level_2").state == "20"
    assert hass.states.get("text.plcnext_message").state == "Hello PLCnext"


async def test_renewals_keep_entities(
    hass: HomeAssistant,
    plcnext_sim: PlcnextSimulator,
    plcnext_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Token expiry, session loss, group expiry and a download: nothing goes unavailable."""
    client = plcnext_entry.runtime_data.client
    for change, shown in (
        (plcnext_sim.access.expire_tokens, "19.5"),
        (plcnext_sim.access.expire_sessions, "19.0"),
        (plcnext_sim.expire_groups, "18.5"),
        (plcnext_sim.download, "18.0"),
    ):
        change()
        plcnext_sim.set("MainInstance.Temperature", float(shown))
        await poll(hass, freezer)
        assert hass.states.get(TEMPERATURE).state == shown
        assert STATE_UNAVAILABLE not in {state.state for state in hass.states.async_all()}
    await poll(hass, freezer)
    assert client.metrics.last_poll_requests == 1


async def test_writes(
    hass: HomeAssistant, plcnext_sim: PlcnextSimulator, plcnext_entry: MockConfigEntry
) -> None:
    """A switch and the write action reach the PLC."""
    await hass.services.async_call(
        SWITCH_DOMAIN, SERVICE_TURN_ON, {ATTR_ENTITY_ID: "switch.plcnext_pump"}, blocking=True
    )
    await hass.async_block_till_done()
    assert plcnext_sim.get("MainInstance.Pump") is True
    assert hass.states.get("switch.plcnext_pump").state == STATE_ON
    await call(
        hass,
        "write",
        plcnext_entry,
        points=[{"address": "MainInstance.Speed", "data_type": "INT", "value": -7}],
    )
    assert plcnext_sim.get("MainInstance.Speed") == -7
