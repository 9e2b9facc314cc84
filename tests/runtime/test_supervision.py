"""Command/feedback supervision: raised when the state does not follow in time, then cleared.

Every kind with a state and a command (switch, light, fan, climate on/off; cover and valve by
their travel time), against the S7-200 SMART and TecoApi simulators with HA's time travel.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.const import ATTR_ENTITY_ID
from homeassistant.core import Event, HomeAssistant
from homeassistant.helpers import issue_registry as ir
import pytest
from pytest_homeassistant_custom_component.common import async_capture_events

from custom_components.plc_bridge.const import DOMAIN
from custom_components.plc_bridge.runtime.supervision import (
    EVENT_FEEDBACK_RESTORED,
    EVENT_FEEDBACK_TIMEOUT,
)
from tests.entries import SCAN_INTERVAL, PointData, point
from tests.harness import OUTPUT_FAMILIES, PlcUnderTest, wait

pytestmark = [
    pytest.mark.no_pacing,
    pytest.mark.parametrize("plc", OUTPUT_FAMILIES, indirect=True),
    pytest.mark.usefixtures("outputs_at_rest"),
]

SECONDS = 25.0
"""The supervision (or travel) time of the test entities: longer than a poll interval."""


@dataclass(frozen=True)
class Kind:
    """A supervised kind: its parts, the action that commands it, what it follows and how."""

    platform: str
    service: str
    commanded: str
    follow: str  # the role whose address the machine sets to follow the command
    reset: str | None = None  # the role the PLC's program sets back after the write


KINDS = {
    "switch": Kind("switch", "turn_on", "on", "open_limit"),
    "light": Kind("light", "turn_on", "on", "open_limit"),
    "fan": Kind("fan", "turn_on", "on", "open_limit"),
    "climate": Kind("climate", "turn_on", "on", "open", reset="open"),
    "cover": Kind("cover", "open_cover", "open", "open_limit"),
    "valve": Kind("valve", "open_valve", "open", "open_limit"),
}


def parts(plc: PlcUnderTest, kind: Kind, seconds: float | None = SECONDS) -> list[PointData]:
    """The test entity's parts, supervised for `seconds` (a cover's or valve's travel time)."""
    name, platform = "Pump", kind.platform
    time = {} if seconds is None else {"supervision": seconds}
    if platform in ("cover", "valve"):
        time = {} if seconds is None else {"travel_time": seconds}
        roles = ("open", "close", "stop", "open_limit", "closed_limit")
        return [plc.part(role, name, platform, **time) for role in roles]
    if platform == "climate":
        address = plc.addresses["open"]
        return [point("on_off", name, platform, address, plc.bit, role="on_off", **time)]
    state, command = plc.addresses["open_limit"], plc.addresses["open"]
    return [
        point("state", name, platform, state, plc.bit, role="state", read_only=True, **time),
        point("command", name, platform, command, plc.bit, role="command", **time),
    ]


async def command(hass: HomeAssistant, plc: PlcUnderTest, kind: Kind) -> None:
    """Send the kind's command; the PLC's program sets a reset role back at once."""
    entity_id = plc.entity(kind.platform, "pump")
    await hass.services.async_call(
        kind.platform, kind.service, {ATTR_ENTITY_ID: entity_id}, blocking=True
    )
    if kind.reset is not None:
        plc.set(kind.reset, False)


def issue(hass: HomeAssistant) -> ir.IssueEntry | None:
    """The feedback issue of the test entry, if raised."""
    issues = ir.async_get(hass).issues
    found = [entry for (domain, key), entry in issues.items() if domain == DOMAIN]
    found = [entry for entry in found if entry.issue_id.startswith("feedback_timeout_")]
    assert len(found) <= 1
    return found[0] if found else None


def captured(hass: HomeAssistant) -> tuple[list[Event[Any]], list[Event[Any]]]:
    """Start capturing the timeout and the restored events."""
    return (
        async_capture_events(hass, EVENT_FEEDBACK_TIMEOUT),
        async_capture_events(hass, EVENT_FEEDBACK_RESTORED),
    )


@pytest.mark.parametrize("name", list(KINDS))
async def test_raised_then_cleared_when_it_follows(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, plc: PlcUnderTest, name: str
) -> None:
    """No state following in time: an event and an issue; the state following clears both."""
    kind = KINDS[name]
    await plc.set_up(hass, parts(plc, kind))
    timeouts, restored = captured(hass)
    await command(hass, plc, kind)
    await wait(hass, freezer, SECONDS - 1)
    assert (timeouts, issue(hass)) == ([], None)
    await wait(hass, freezer, 2)
    entity_id = plc.entity(kind.platform, "pump")
    assert [event.data for event in timeouts] == [
        {
            "entity_id": entity_id,
            "name": "Pump",
            "commanded": kind.commanded,
            "state": hass.states.get(entity_id).state,  # type: ignore[union-attr]
            "seconds": SECONDS,
        }
    ]
    raised = issue(hass)
    assert raised is not None
    assert raised.translation_key == f"feedback_{kind.commanded}"
    assert raised.translation_placeholders is not None
    assert raised.translation_placeholders["name"] == "Pump"
    assert raised.translation_placeholders["seconds"] == f"{SECONDS:g}"
    assert restored == []
    plc.set(kind.follow, True)
    await wait(hass, freezer, SCAN_INTERVAL)
    assert issue(hass) is None
    assert [event.data["commanded"] for event in restored] == [kind.commanded]
    assert len(timeouts) == 1


@pytest.mark.parametrize("name", list(KINDS))
async def test_not_raised_when_it_follows_in_time(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, plc: PlcUnderTest, name: str
) -> None:
    """The state following before the time is up: no event, no issue, then or later."""
    kind = KINDS[name]
    await plc.set_up(hass, parts(plc, kind))
    timeouts, restored = captured(hass)
    await command(hass, plc, kind)
    plc.set(kind.follow, True)
    await wait(hass, freezer, SCAN_INTERVAL)
    await wait(hass, freezer, SECONDS)
    await wait(hass, freezer, SECONDS)
    assert (timeouts, restored, issue(hass)) == ([], [], None)


async def test_not_supervised_without_a_time(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, plc: PlcUnderTest
) -> None:
    """A switch without a supervision time raises nothing, however long its state lags."""
    kind = KINDS["switch"]
    await plc.set_up(hass, parts(plc, kind, seconds=None))
    timeouts, _ = captured(hass)
    await command(hass, plc, kind)
    await wait(hass, freezer, SECONDS * 3)
    assert (timeouts, issue(hass)) == ([], None)


async def test_reload_cancels_and_a_left_issue_is_cleared(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, plc: PlcUnderTest
) -> None:
    """A reload cancels a pending timer; an issue raised before it is cleared by a poll after."""
    kind = KINDS["switch"]
    entry = await plc.set_up(hass, parts(plc, kind))
    timeouts, restored = captured(hass)
    await command(hass, plc, kind)
    assert await hass.config_entries.async_reload(entry.entry_id)
    await hass.async_block_till_done()
    await wait(hass, freezer, SECONDS * 2)
    assert (timeouts, issue(hass)) == ([], None)
    await command(hass, plc, kind)
    await wait(hass, freezer, SECONDS + 1)
    assert len(timeouts) == 1
    assert await hass.config_entries.async_reload(entry.entry_id)
    await hass.async_block_till_done()
    assert issue(hass) is not None  # kept across the reload: the state still does not follow
    await wait(hass, freezer, SCAN_INTERVAL)
    assert issue(hass) is not None
    plc.set(kind.follow, True)
    await wait(hass, freezer, SCAN_INTERVAL)
    assert issue(hass) is None
    assert [event.data["commanded"] for event in restored] == ["on"]


async def test_a_stop_withdraws_the_cover_issue(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, plc: PlcUnderTest
) -> None:
    """A cover stopped by hand ends the watch of its open: its issue goes, no event says so."""
    kind = KINDS["cover"]
    await plc.set_up(hass, parts(plc, kind))
    timeouts, restored = captured(hass)
    await command(hass, plc, kind)
    await wait(hass, freezer, SECONDS + 1)
    assert len(timeouts) == 1
    assert issue(hass) is not None
    await hass.services.async_call(
        "cover", "stop_cover", {ATTR_ENTITY_ID: plc.entity("cover", "pump")}, blocking=True
    )
    assert issue(hass) is None
    assert restored == []
