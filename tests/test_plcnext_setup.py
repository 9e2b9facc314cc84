"""A PLCnext Control end to end: live values, renewals mid-polling, writes."""

from __future__ import annotations

from datetime import datetime

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.switch import DOMAIN as SWITCH_DOMAIN, SERVICE_TURN_ON
from homeassistant.config_entries import ConfigEntryState
from homeassistant.const import ATTR_ENTITY_ID, STATE_OFF, STATE_ON, STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.helpers import entity_registry as er, issue_registry as ir
from homeassistant.util import dt as dt_util
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import DOMAIN
from simulators.plcnext import PlcnextSimulator
from tests.entries import call, point, poll
from tests.harness import make_plcnext_entry

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
    plcnext_ha_sim: PlcnextSimulator,
    plcnext_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Token expiry, session loss, group expiry and a download: nothing goes unavailable."""
    client = plcnext_entry.runtime_data.client
    for change, shown in (
        (plcnext_ha_sim.access.expire_tokens, "19.5"),
        (plcnext_ha_sim.access.expire_sessions, "19.0"),
        (plcnext_ha_sim.expire_groups, "18.5"),
        (plcnext_ha_sim.download, "18.0"),
    ):
        change()
        plcnext_ha_sim.set("MainInstance.Temperature", float(shown))
        await poll(hass, freezer)
        assert hass.states.get(TEMPERATURE).state == shown
        assert STATE_UNAVAILABLE not in {state.state for state in hass.states.async_all()}
    await poll(hass, freezer)
    assert client.metrics.last_poll_requests == 1


async def test_writes(
    hass: HomeAssistant, plcnext_ha_sim: PlcnextSimulator, plcnext_entry: MockConfigEntry
) -> None:
    """A switch and the write action reach the PLC."""
    await hass.services.async_call(
        SWITCH_DOMAIN, SERVICE_TURN_ON, {ATTR_ENTITY_ID: "switch.plcnext_pump"}, blocking=True
    )
    await hass.async_block_till_done()
    assert plcnext_ha_sim.get("MainInstance.Pump") is True
    assert hass.states.get("switch.plcnext_pump").state == STATE_ON
    await call(
        hass,
        "write",
        plcnext_entry,
        points=[{"address": "MainInstance.Speed", "data_type": "INT", "value": -7}],
    )
    assert plcnext_ha_sim.get("MainInstance.Speed") == -7


def issue_of(entry: MockConfigEntry, point_id: str) -> str:
    """Return the issue id of a point the PLC does not know."""
    return f"unknown_address_{entry.entry_id}_{point_id}"


async def test_renamed_variable_raises_an_issue(
    hass: HomeAssistant,
    plcnext_ha_sim: PlcnextSimulator,
    plcnext_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    issue_registry: ir.IssueRegistry,
) -> None:
    """A download that renames a variable: its point alone goes, with an issue naming it.

    The project checksum (a diagnostic sensor, on by default) shows the download.
    """
    checksum = "sensor.plcnext_project_checksum"
    assert hass.states.get(checksum).state == str(plcnext_ha_sim.crc)
    plcnext_ha_sim.download({"Arp.Plc.Eclr/MainInstance.Pump": "Arp.Plc.Eclr/MainInstance.PumpOn"})
    plcnext_ha_sim.set("MainInstance.Temperature", 19.5)
    await poll(hass, freezer)
    unavailable = [s.entity_id for s in hass.states.async_all() if s.state == STATE_UNAVAILABLE]
    assert unavailable == ["switch.plcnext_pump"]
    assert hass.states.get(TEMPERATURE).state == "19.5"
    assert hass.states.get(checksum).state == str(plcnext_ha_sim.crc)
    issue = issue_registry.async_get_issue(DOMAIN, issue_of(plcnext_entry, "pump"))
    assert issue is not None
    assert issue.translation_key == "unknown_address"
    assert not issue.is_fixable
    placeholders = issue.translation_placeholders or {}
    assert placeholders["address"] == "Arp.Plc.Eclr/MainInstance.Pump"
    assert "does not know this variable, or it has no HMI flag" in placeholders["error"]
    await poll(hass, freezer)
    assert plcnext_entry.runtime_data.client.metrics.last_poll_requests == 1
    assert len(issue_registry.issues) == 1

    plcnext_ha_sim.download({"Arp.Plc.Eclr/MainInstance.PumpOn": "Arp.Plc.Eclr/MainInstance.Pump"})
    await poll(hass, freezer)  # the new projectCRC: the name is asked for again at once
    assert hass.states.get("switch.plcnext_pump").state == STATE_OFF
    assert not issue_registry.issues


async def test_unknown_from_the_start(
    hass: HomeAssistant,
    plcnext_ha_sim: PlcnextSimulator,
    freezer: FrozenDateTimeFactory,
    issue_registry: ir.IssueRegistry,
) -> None:
    """Every point unknown (no HMI flag yet): issues; once the project is fixed, values show."""
    entry = make_plcnext_entry(
        hass,
        plcnext_ha_sim,
        [point("later", "Later", "sensor", "MainInstance.Later", "INT")],
        vendor_options={},
    )
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert hass.states.get("sensor.plcnext_later").state == STATE_UNAVAILABLE
    assert issue_registry.async_get_issue(DOMAIN, issue_of(entry, "later")) is not None
    plcnext_ha_sim.download({"Arp.Plc.Eclr/MainInstance.Speed": "Arp.Plc.Eclr/MainInstance.Later"})
    await poll(hass, freezer)
    assert hass.states.get("sensor.plcnext_later").state == "-1200"
    assert not issue_registry.issues


async def test_clock_and_sync(
    hass: HomeAssistant,
    plcnext_ha_sim: PlcnextSimulator,
    plcnext_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    entity_registry: er.EntityRegistry,
) -> None:
    """The clock variable rides in the poll's group; sync_clock writes it."""
    clock = entity_registry.async_get("datetime.plcnext_plc_clock")
    assert clock is not None
    assert clock.disabled_by is not None  # off by default, as for every vendor
    drift = hass.states.get("sensor.plcnext_clock_drift")
    assert drift is not None
    assert int(drift.state) != 0
    now = dt_util.utcnow()
    await call(hass, "sync_clock", plcnext_entry)
    stored = datetime.fromisoformat(plcnext_ha_sim.get("MainInstance.Clock"))
    assert abs((stored - now).total_seconds()) < 1
    assert hass.states.get("sensor.plcnext_clock_drift").state == "0"
