"""Pulses: the off written whatever the on's outcome, retried until confirmed, kept end.

Run against the S7-200 SMART and TecoApi simulators, with HA's time travel and write faults.
"""

from __future__ import annotations

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.button import DOMAIN as BUTTON_DOMAIN, SERVICE_PRESS
from homeassistant.components.cover import DOMAIN as COVER_DOMAIN, SERVICE_STOP_COVER
from homeassistant.const import ATTR_ENTITY_ID
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import HomeAssistantError
from homeassistant.helpers import issue_registry as ir
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import DOMAIN
from tests.entries import point
from tests.harness import OUTPUT_FAMILIES, Faults, PlcUnderTest, wait

pytestmark = [
    pytest.mark.no_pacing,
    pytest.mark.parametrize("plc", OUTPUT_FAMILIES, indirect=True),
    pytest.mark.usefixtures("outputs_at_rest"),
]

PULSE = 2.0


async def set_up_button(
    hass: HomeAssistant, plc: PlcUnderTest, faults: Faults, monkeypatch: pytest.MonkeyPatch
) -> MockConfigEntry:
    """Set up the PLC with a pulse button; its writes go through the fault queue."""
    step = point("step", "Step", "button", plc.addresses["button"], plc.bit, pulse=PULSE)
    entry = await plc.set_up(hass, [step])
    faults.wrap(entry.runtime_data.client, monkeypatch)
    return entry


async def press(hass: HomeAssistant, plc: PlcUnderTest) -> None:
    """Press the pulse button."""
    await hass.services.async_call(
        BUTTON_DOMAIN, SERVICE_PRESS, {ATTR_ENTITY_ID: plc.entity("button", "step")}, True
    )


def offs(faults: Faults) -> list[bool]:
    """Whether each write to the button was an off, and whether it went as urgent."""
    address = faults.plc.addresses["button"]
    return [(not values[address], urgent) for values, urgent in faults.writes]


@pytest.mark.parametrize("fault", ["lost_answer", "dropped"])
async def test_off_after_an_on_that_failed(
    hass: HomeAssistant,
    *,
    freezer: FrozenDateTimeFactory,
    plc: PlcUnderTest,
    faults: Faults,
    monkeypatch: pytest.MonkeyPatch,
    fault: str,
) -> None:
    """An on-write that timed out may have landed: its off follows after the pulse, urgently."""
    await set_up_button(hass, plc, faults, monkeypatch)
    faults.queue.append(fault)
    with pytest.raises(HomeAssistantError):
        await press(hass, plc)
    assert plc.get("button") is (fault == "lost_answer")
    await wait(hass, freezer, PULSE + 0.1)
    assert plc.get("button") is False
    assert offs(faults) == [(False, False), (True, True)]


async def test_off_retried_until_confirmed(
    hass: HomeAssistant,
    *,
    freezer: FrozenDateTimeFactory,
    plc: PlcUnderTest,
    faults: Faults,
    monkeypatch: pytest.MonkeyPatch,
    issue_registry: ir.IssueRegistry,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """An off the PLC does not confirm: an issue names it, retried with back-off until written."""
    entry = await set_up_button(hass, plc, faults, monkeypatch)
    issue = f"pulse_failed_{entry.entry_id}_step"
    await press(hass, plc)
    faults.queue.extend(["dropped", "dropped"])
    await wait(hass, freezer, PULSE + 0.1)
    assert plc.get("button") is True
    assert issue_registry.async_get_issue(DOMAIN, issue).translation_placeholders["point"] == "Step"
    with pytest.raises(HomeAssistantError, match="not released yet"):
        await press(hass, plc)
    await wait(hass, freezer, 1.1)
    assert plc.get("button") is True
    assert issue_registry.async_get_issue(DOMAIN, issue) is not None
    await wait(hass, freezer, 2.1)
    assert plc.get("button") is False
    assert issue_registry.async_get_issue(DOMAIN, issue) is None
    assert offs(faults) == [(False, False), (True, True), (True, True), (True, True)]
    assert caplog.text.count("could not be released") == 1


async def test_second_press_keeps_the_end(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    plc: PlcUnderTest,
    faults: Faults,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A press during a pulse writes nothing and keeps the first pulse's end."""
    await set_up_button(hass, plc, faults, monkeypatch)
    await press(hass, plc)
    await wait(hass, freezer, 1.0)
    await press(hass, plc)
    assert plc.get("button") is True
    await wait(hass, freezer, 1.1)
    assert plc.get("button") is False
    assert offs(faults) == [(False, False), (True, True)]


async def test_reload_releases_what_unload_could_not(
    hass: HomeAssistant,
    *,
    plc: PlcUnderTest,
    faults: Faults,
    monkeypatch: pytest.MonkeyPatch,
    issue_registry: ir.IssueRegistry,
) -> None:
    """An off that failed at unload is written when the entry is set up again."""
    entry = await set_up_button(hass, plc, faults, monkeypatch)
    issue = f"pulse_failed_{entry.entry_id}_step"
    await press(hass, plc)
    faults.queue.append("dropped")
    assert await hass.config_entries.async_unload(entry.entry_id)
    assert plc.get("button") is True
    assert issue_registry.async_get_issue(DOMAIN, issue) is not None
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done(wait_background_tasks=True)
    assert plc.get("button") is False
    assert issue_registry.async_get_issue(DOMAIN, issue) is None


async def test_command_pulse_ends_after_a_lost_answer(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    plc: PlcUnderTest,
    faults: Faults,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A cover's pulsed stop whose on-write timed out is ended as a button's pulse is."""
    parts = [plc.part("open"), plc.part("close"), plc.part("stop", pulse=1.0)]
    entry = await plc.set_up(hass, parts)
    faults.wrap(entry.runtime_data.client, monkeypatch)
    faults.queue.append("lost_answer")
    with pytest.raises(HomeAssistantError):
        await hass.services.async_call(
            COVER_DOMAIN, SERVICE_STOP_COVER, {ATTR_ENTITY_ID: plc.entity("cover")}, True
        )
    assert (plc.get("stop"), plc.get("open"), plc.get("close")) == (True, False, False)
    await wait(hass, freezer, 1.1)
    assert plc.get("stop") is False
    assert faults.writes[-1][1] is True
