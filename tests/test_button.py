"""Tests of the buttons: a single write (the PLC resets the bit) or a pulse timed by HA."""

from __future__ import annotations

from datetime import timedelta

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.button import DOMAIN as BUTTON_DOMAIN, SERVICE_PRESS
from homeassistant.const import ATTR_ENTITY_ID, EVENT_HOMEASSISTANT_STOP
from homeassistant.core import HomeAssistant
from homeassistant.helpers import issue_registry as ir
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, async_fire_time_changed

from custom_components.plc_bridge.const import DOMAIN
from simulators.s7_smart import S7SmartSimulator
from tests.entries import ENTRY_ID, make_entry, point

pytestmark = pytest.mark.no_pacing

POINTS = [
    point("start", "Start", "button", "VB60", "unsigned"),
    point("step", "Step", "button", "Q0.2", "signed", pulse=2.0),
    point("reset", "Reset", "button", "VW62", "signed", on_value=7, off_value=3, pulse=0.5),
]
ISSUE = f"pulse_failed_{ENTRY_ID}_step"


@pytest.fixture
async def buttons(hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator) -> MockConfigEntry:
    """The simulator's entry with a write-once button and two pulse buttons, set up."""
    entry = make_entry(hass, s7_smart_ha_sim, POINTS)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    return entry


async def press(hass: HomeAssistant, name: str) -> None:
    """Press a button of the test PLC."""
    await hass.services.async_call(
        BUTTON_DOMAIN, SERVICE_PRESS, {ATTR_ENTITY_ID: f"button.s7_200_smart_{name}"}, blocking=True
    )


async def wait(hass: HomeAssistant, freezer: FrozenDateTimeFactory, seconds: float) -> None:
    """Let time pass and the timers due run."""
    freezer.tick(timedelta(seconds=seconds))
    async_fire_time_changed(hass)
    await hass.async_block_till_done(wait_background_tasks=True)


async def test_write_once(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    s7_smart_ha_sim: S7SmartSimulator,
    buttons: MockConfigEntry,
) -> None:
    """The safe mode: one write of the on value; the PLC program resets it."""
    await press(hass, "start")
    assert s7_smart_ha_sim.get("VB60", "unsigned") == 1
    await wait(hass, freezer, 60)
    assert s7_smart_ha_sim.calls["write"] == 1


async def test_pulse(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    s7_smart_ha_sim: S7SmartSimulator,
    buttons: MockConfigEntry,
) -> None:
    """On, then off once the pulse's time is up, with the point's own codes."""
    await press(hass, "step")
    assert s7_smart_ha_sim.get("Q0.2") is True
    await wait(hass, freezer, 0.5)
    assert s7_smart_ha_sim.get("Q0.2") is True
    await wait(hass, freezer, 2)
    assert s7_smart_ha_sim.get("Q0.2") is False
    await press(hass, "reset")
    assert s7_smart_ha_sim.get("VW62") == 7
    await wait(hass, freezer, 0.6)
    assert s7_smart_ha_sim.get("VW62") == 3
    assert s7_smart_ha_sim.calls["write"] == 4


async def test_failed_off_write_retried_then_reported(
    hass: HomeAssistant,
    *,
    freezer: FrozenDateTimeFactory,
    s7_smart_ha_sim: S7SmartSimulator,
    buttons: MockConfigEntry,
    issue_registry: ir.IssueRegistry,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """The off-write is logged once and raised, then retried until it is written."""
    await press(hass, "step")
    s7_smart_ha_sim.mode = "STOP"
    await wait(hass, freezer, 2.5)
    assert s7_smart_ha_sim.get("Q0.2") is True
    assert s7_smart_ha_sim.calls["write"] == 2
    issue = issue_registry.async_get_issue(DOMAIN, ISSUE)
    assert issue is not None
    assert issue.translation_placeholders["address"] == "Q0.2"
    assert caplog.text.count("Q0.2 could not be released") == 1
    s7_smart_ha_sim.mode = "RUN"
    await wait(hass, freezer, 1.1)
    assert s7_smart_ha_sim.get("Q0.2") is False
    assert s7_smart_ha_sim.calls["write"] == 3
    assert issue_registry.async_get_issue(DOMAIN, ISSUE) is None


async def test_unload_mid_pulse_ends_it(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, buttons: MockConfigEntry
) -> None:
    await press(hass, "step")
    assert await hass.config_entries.async_unload(buttons.entry_id)
    assert s7_smart_ha_sim.get("Q0.2") is False


async def test_stop_mid_pulse_ends_it(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, buttons: MockConfigEntry
) -> None:
    await press(hass, "step")
    hass.bus.async_fire(EVENT_HOMEASSISTANT_STOP)
    await hass.async_block_till_done()
    assert s7_smart_ha_sim.get("Q0.2") is False
    assert s7_smart_ha_sim.calls["write"] == 2
