"""Tests of covers built from several points, against the S7-200 SMART simulator."""

from __future__ import annotations

from datetime import timedelta
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.cover import (
    ATTR_CURRENT_POSITION,
    ATTR_CURRENT_TILT_POSITION,
    ATTR_POSITION,
    ATTR_TILT_POSITION,
    DOMAIN as COVER_DOMAIN,
    SERVICE_CLOSE_COVER,
    SERVICE_OPEN_COVER,
    SERVICE_SET_COVER_POSITION,
    SERVICE_SET_COVER_TILT_POSITION,
    SERVICE_STOP_COVER,
    CoverEntityFeature,
)
from homeassistant.const import ATTR_ENTITY_ID, ATTR_SUPPORTED_FEATURES, STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import ServiceValidationError
from homeassistant.helpers import entity_registry as er, issue_registry as ir
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, async_fire_time_changed

from custom_components.plc_bridge.const import DOMAIN
from simulators.s7_smart import S7SmartSimulator
from tests.entries import ENTRY_ID, edit_point, make_entry, point, poll, set_points

pytestmark = pytest.mark.no_pacing

RANGE = {"raw_min": 0, "raw_max": 27648, "shown_min": 0, "shown_max": 100}
SHUTTER = [
    point("s1", "Shutter", "cover", "VW40", "signed", role="position", read_only=True, **RANGE),
    point("s2", "Shutter", "cover", "VW42", "signed", role="set_position", **RANGE),
    point("s3", "Shutter", "cover", "Q0.4", "signed", role="open"),
    point("s4", "Shutter", "cover", "Q0.5", "signed", role="close"),
    point("s5", "Shutter", "cover", "Q0.6", "signed", role="stop", pulse=1.0),
    point("s6", "Shutter", "cover", "I0.1", "signed", role="open_limit", read_only=True),
    point("s7", "Shutter", "cover", "I0.2", "signed", role="closed_limit", read_only=True),
]
BLIND = [
    point(
        "b1",
        "Blind",
        "cover",
        "VW44",
        "signed",
        role="status",
        read_only=True,
        value_map="0=closed;1=opening;2=open;3=closing",
    ),
    point("b2", "Blind", "cover", "VW46", "signed", role="position", invert=True),
]
SHUTTER_ID = "cover.s7_200_smart_shutter"
BLIND_ID = "cover.s7_200_smart_blind"


async def set_up(hass: HomeAssistant, sim: S7SmartSimulator, points: list[Any]) -> MockConfigEntry:
    """Set up the simulator's entry with these points."""
    entry = make_entry(hass, sim, points)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    return entry


async def cover(hass: HomeAssistant, service: str, entity_id: str, **data: Any) -> None:
    """Call a cover action."""
    await hass.services.async_call(
        COVER_DOMAIN, service, {ATTR_ENTITY_ID: entity_id, **data}, blocking=True
    )


async def test_shutter(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """Position read through the range, commands written, stop pulsed, limits give the state."""
    s7_smart_ha_sim.set("VW40", 13824)
    await set_up(hass, s7_smart_ha_sim, SHUTTER)
    state = hass.states.get(SHUTTER_ID)
    assert state.state == "open"
    assert state.attributes[ATTR_CURRENT_POSITION] == 50
    assert state.attributes[ATTR_SUPPORTED_FEATURES] == (
        CoverEntityFeature.OPEN
        | CoverEntityFeature.CLOSE
        | CoverEntityFeature.STOP
        | CoverEntityFeature.SET_POSITION
    )
    await cover(hass, SERVICE_OPEN_COVER, SHUTTER_ID)
    assert s7_smart_ha_sim.get("Q0.4") is True
    await cover(hass, SERVICE_SET_COVER_POSITION, SHUTTER_ID, **{ATTR_POSITION: 25})
    assert s7_smart_ha_sim.get("VW42") == 6912
    await cover(hass, SERVICE_STOP_COVER, SHUTTER_ID)
    assert s7_smart_ha_sim.get("Q0.6") is True
    freezer.tick(timedelta(seconds=1.1))
    async_fire_time_changed(hass)
    await hass.async_block_till_done(wait_background_tasks=True)
    assert s7_smart_ha_sim.get("Q0.6") is False
    s7_smart_ha_sim.set("I0.2", True)
    s7_smart_ha_sim.set("VW40", 0)
    await poll(hass, freezer)
    assert hass.states.get(SHUTTER_ID).state == "closed"
    assert s7_smart_ha_sim.calls["read"] >= 1


async def test_status_map_and_inverted_position(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """The status map names the state; an inverted position counts 0 as open."""
    s7_smart_ha_sim.set("VW44", 1)
    s7_smart_ha_sim.set("VW46", 30)
    await set_up(hass, s7_smart_ha_sim, BLIND)
    state = hass.states.get(BLIND_ID)
    assert state.state == "opening"
    assert state.attributes[ATTR_CURRENT_POSITION] == 70
    await cover(hass, SERVICE_SET_COVER_POSITION, BLIND_ID, **{ATTR_POSITION: 90})
    assert s7_smart_ha_sim.get("VW46") == 10
    await cover(hass, SERVICE_CLOSE_COVER, BLIND_ID)
    assert s7_smart_ha_sim.get("VW46") == 100
    s7_smart_ha_sim.set("VW44", 0)
    await poll(hass, freezer)
    assert hass.states.get(BLIND_ID).state == "closed"


async def test_one_poll_for_every_part(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """The parts of two covers join the one planned read: one request per poll."""
    await set_up(hass, s7_smart_ha_sim, [*SHUTTER, *BLIND])
    reads = s7_smart_ha_sim.calls["read"]
    await poll(hass, freezer)
    assert s7_smart_ha_sim.calls["read"] == reads + 1


async def test_failing_part_alone(hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator) -> None:
    """A part at a bad address shows as unknown; a cover with no part that reads is unavailable."""
    s7_smart_ha_sim.set("I0.2", True)
    points = [
        point("s1", "Shutter", "cover", "VW30000", "signed", role="position", read_only=True),
        point("s7", "Shutter", "cover", "I0.2", "signed", role="closed_limit", read_only=True),
        point("g1", "Gate", "cover", "VW30002", "signed", role="position"),
    ]
    await set_up(hass, s7_smart_ha_sim, points)
    state = hass.states.get(SHUTTER_ID)
    assert state.state == "closed"
    assert ATTR_CURRENT_POSITION not in state.attributes
    assert hass.states.get("cover.s7_200_smart_gate").state == STATE_UNAVAILABLE


async def test_refused_write(hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator) -> None:
    """A command at a read-only part's address is refused before anything is sent."""
    points = [
        *SHUTTER[:3],
        point("guard", "Guard", "binary_sensor", "Q0.4", "signed", read_only=True),
    ]
    await set_up(hass, s7_smart_ha_sim, points)
    with pytest.raises(ServiceValidationError) as err:
        await cover(hass, SERVICE_OPEN_COVER, SHUTTER_ID)
    assert err.value.translation_key == "read_only"
    assert s7_smart_ha_sim.calls["write"] == 0


async def test_edited_part_keeps_the_entity(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    entity_registry: er.EntityRegistry,
) -> None:
    """Editing one part rebuilds the cover under the same entity id."""
    entry = await set_up(hass, s7_smart_ha_sim, SHUTTER)
    before = entity_registry.async_get(SHUTTER_ID)
    edit_point(hass, entry, "s2", address="VW48")
    await hass.async_block_till_done()
    await cover(hass, SERVICE_SET_COVER_POSITION, SHUTTER_ID, **{ATTR_POSITION: 100})
    assert s7_smart_ha_sim.get("VW48") == 27648
    assert entity_registry.async_get(SHUTTER_ID).id == before.id


async def test_added_part_keeps_the_entity(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    entity_registry: er.EntityRegistry,
) -> None:
    """A part added later (its id sorting first) joins the cover under the same entity."""
    parts = [(pid, {**data, "entity": "s1"}) for pid, data in SHUTTER[:3]]
    entry = await set_up(hass, s7_smart_ha_sim, parts)
    before = entity_registry.async_get(SHUTTER_ID)
    stop = point("a0", "Shutter", "cover", "Q0.6", "signed", role="stop", entity="s1")
    set_points(hass, entry, dict([*parts, stop]))
    await hass.async_block_till_done()
    assert entity_registry.async_get(SHUTTER_ID).id == before.id
    await cover(hass, SERVICE_STOP_COVER, SHUTTER_ID)
    assert s7_smart_ha_sim.get("Q0.6") is True


async def test_pulse_ends_at_unload_and_failures_are_reported(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    s7_smart_ha_sim: S7SmartSimulator,
    issue_registry: ir.IssueRegistry,
) -> None:
    """A command's pulse is ended as a button's is: retried, reported, ended at unload."""
    entry = await set_up(hass, s7_smart_ha_sim, SHUTTER)
    await cover(hass, SERVICE_STOP_COVER, SHUTTER_ID)
    s7_smart_ha_sim.mode = "STOP"
    freezer.tick(timedelta(seconds=1.1))
    async_fire_time_changed(hass)
    await hass.async_block_till_done(wait_background_tasks=True)
    assert s7_smart_ha_sim.get("Q0.6") is True
    assert s7_smart_ha_sim.calls["write"] == 2
    assert issue_registry.async_get_issue(DOMAIN, f"pulse_failed_{ENTRY_ID}_s1_stop")
    s7_smart_ha_sim.mode = "RUN"
    assert await hass.config_entries.async_unload(entry.entry_id)
    assert s7_smart_ha_sim.get("Q0.6") is False
    assert issue_registry.async_get_issue(DOMAIN, f"pulse_failed_{ENTRY_ID}_s1_stop") is None


async def test_step_relay_and_tilt(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """A step-relay button pulsed by open, stop and close; the tilt set through its range."""
    s7_smart_ha_sim.set("VW90", 50)
    points = [
        point("k1", "Awning", "cover", "Q1.2", "signed", role="step", pulse=0.5),
        point("k2", "Awning", "cover", "VW90", "signed", role="tilt_position"),
        point("k3", "Awning", "cover", "VW92", "signed", role="set_tilt_position", invert=True),
    ]
    await set_up(hass, s7_smart_ha_sim, points)
    awning = "cover.s7_200_smart_awning"
    assert hass.states.get(awning).attributes[ATTR_CURRENT_TILT_POSITION] == 50
    for service in (SERVICE_OPEN_COVER, SERVICE_STOP_COVER, SERVICE_CLOSE_COVER):
        await cover(hass, service, awning)
        assert s7_smart_ha_sim.get("Q1.2") is True
        freezer.tick(timedelta(seconds=0.6))
        async_fire_time_changed(hass)
        await hass.async_block_till_done(wait_background_tasks=True)
        assert s7_smart_ha_sim.get("Q1.2") is False
    await cover(hass, SERVICE_SET_COVER_TILT_POSITION, awning, **{ATTR_TILT_POSITION: 30})
    assert s7_smart_ha_sim.get("VW92") == 70
