"""Exposes in detail, on the S7-200 SMART: attributes, maps, cooldown, resend, start, failures."""

from __future__ import annotations

import logging

from freezegun.api import FrozenDateTimeFactory
from homeassistant.core import HomeAssistant
from homeassistant.helpers import entity_registry as er, issue_registry as ir
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from pytest_homeassistant_custom_component.components.diagnostics import (
    get_diagnostics_for_config_entry,
)
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.plc_bridge.const import DOMAIN
from custom_components.plc_bridge.runtime.expose import FAILURE_LIMIT
from custom_components.plc_bridge.runtime.issues import expose_issue_id
from simulators.s7_smart import S7SmartSimulator
from tests.entries import make_entry, point, set_up
from tests.harness import add_expose, settle

pytestmark = pytest.mark.no_pacing

WEATHER = "weather.home"
LEVEL = "input_number.level"
REAL = ("VD400", "float")
WORD = ("VW120", "signed")
BIT = ("M10.0", "signed")


@pytest.fixture
def entry(hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator) -> MockConfigEntry:
    """An S7-200 SMART entry with one polled point (not set up), and the entities exposed."""
    hass.states.async_set(WEATHER, "sunny", {"temperature": 3.5})
    hass.states.async_set(LEVEL, "10")
    return make_entry(hass, s7_smart_ha_sim, [point("level", "Level", "sensor", "VW50", "signed")])


def writes(sim: S7SmartSimulator) -> int:
    """Return the write requests the simulator has served."""
    return sim.calls["write"]


async def test_attribute_and_unchanged_value(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    entry: MockConfigEntry,
    s7_smart_ha_sim: S7SmartSimulator,
) -> None:
    """An attribute is written; a state change that leaves its value as it was writes nothing."""
    add_expose(hass, entry, WEATHER, REAL, attribute="temperature", scale=2.0, offset=1.0)
    await set_up(hass, entry)
    hass.states.async_set(WEATHER, "sunny", {"temperature": 5.25})
    await settle(hass, freezer)
    assert s7_smart_ha_sim.get(*REAL) == 11.5
    before = writes(s7_smart_ha_sim)
    hass.states.async_set(WEATHER, "cloudy", {"temperature": 5.25})
    await settle(hass, freezer, 2.0)
    assert writes(s7_smart_ha_sim) == before


@pytest.mark.parametrize(
    ("value_map", "states", "written"),
    [
        ("open=1;closed=0", ["open", "closed"], [1, 0]),
        ("", ["on", "off"], [1, 0]),  # a switch's words without a map
        ("1=heat;0=off", ["heat", "off"], [1, 0]),  # the point's order is taken too
    ],
)
async def test_states_to_bits(  # noqa: PLR0917
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    entry: MockConfigEntry,
    s7_smart_ha_sim: S7SmartSimulator,
    value_map: str,
    states: list[str],
    written: list[int],
) -> None:
    """Text states become the map's values (on/off without one) on a bit."""
    add_expose(hass, entry, "cover.garage", BIT, value_map=value_map)
    await set_up(hass, entry)
    for state, value in zip(states, written, strict=True):
        hass.states.async_set("cover.garage", state)
        await settle(hass, freezer, 1.0)
        assert s7_smart_ha_sim.get(*BIT) == value


async def test_cooldown_sends_the_last_value_when_it_ends(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    entry: MockConfigEntry,
    s7_smart_ha_sim: S7SmartSimulator,
) -> None:
    """Changes within the cooldown wait for its end; then only the latest is written."""
    add_expose(hass, entry, LEVEL, WORD, cooldown=5.0)
    await set_up(hass, entry)
    hass.states.async_set(LEVEL, "11")
    await settle(hass, freezer)
    before = writes(s7_smart_ha_sim)
    for value in ("12", "13", "14"):
        hass.states.async_set(LEVEL, value)
        await settle(hass, freezer, 1.0)
    assert s7_smart_ha_sim.get(*WORD) == 11
    assert writes(s7_smart_ha_sim) == before
    await settle(hass, freezer, 2.0)  # the cooldown ends 5 s after the first write
    assert s7_smart_ha_sim.get(*WORD) == 14
    assert writes(s7_smart_ha_sim) == before + 1


async def test_periodic_resend(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    entry: MockConfigEntry,
    s7_smart_ha_sim: S7SmartSimulator,
) -> None:
    """The last value is written again every resend period; not once the entity is unavailable."""
    add_expose(hass, entry, LEVEL, WORD, resend=30.0, send_on_start=True)
    await set_up(hass, entry)
    await settle(hass, freezer)
    assert s7_smart_ha_sim.get(*WORD) == 10
    s7_smart_ha_sim.set(WORD[0], 99)
    before = writes(s7_smart_ha_sim)
    await settle(hass, freezer, 30.0)
    assert s7_smart_ha_sim.get(*WORD) == 10
    assert writes(s7_smart_ha_sim) == before + 1
    hass.states.async_set(LEVEL, "unavailable")
    s7_smart_ha_sim.set(WORD[0], 99)
    await settle(hass, freezer, 30.0)
    assert s7_smart_ha_sim.get(*WORD) == 99  # an unavailable entity's last value is not resent


async def test_send_on_start_after_a_reload(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    entry: MockConfigEntry,
    s7_smart_ha_sim: S7SmartSimulator,
) -> None:
    """Send-on-start writes the current state at setup and again after a reload; off: not."""
    add_expose(hass, entry, LEVEL, WORD, send_on_start=True)
    add_expose(hass, entry, WEATHER, REAL, attribute="temperature")
    await set_up(hass, entry)
    await settle(hass, freezer)
    assert s7_smart_ha_sim.get(*WORD) == 10
    assert s7_smart_ha_sim.get(*REAL) == 0.0
    s7_smart_ha_sim.set(WORD[0], 99)
    assert await hass.config_entries.async_reload(entry.entry_id)
    await settle(hass, freezer)
    assert s7_smart_ha_sim.get(*WORD) == 10
    assert s7_smart_ha_sim.get(*REAL) == 0.0


async def test_value_out_of_range_logged_once(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    entry: MockConfigEntry,
    s7_smart_ha_sim: S7SmartSimulator,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """A value the address cannot hold is refused before sending, and logged once."""
    add_expose(hass, entry, LEVEL, WORD, scale=1000.0)
    await set_up(hass, entry)
    before = writes(s7_smart_ha_sim)
    for value in ("40", "50", "sunny"):
        hass.states.async_set(LEVEL, value)
        await settle(hass, freezer, 2.0)
    assert writes(s7_smart_ha_sim) == before
    assert s7_smart_ha_sim.get(*WORD) == 0
    refused = [r for r in caplog.records if "cannot be written to VW120, nothing sent" in r.message]
    assert len(refused) == 1
    assert "40000 is outside -32768..32767" in refused[0].message
    hass.states.async_set(LEVEL, "12")
    await settle(hass, freezer, 2.0)
    assert s7_smart_ha_sim.get(*WORD) == 12000


async def test_failing_writes_raise_an_issue_cleared_on_success(  # noqa: PLR0917
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    entry: MockConfigEntry,
    s7_smart_ha_sim: S7SmartSimulator,
    caplog: pytest.LogCaptureFixture,
    issue_registry: ir.IssueRegistry,
) -> None:
    """A CPU in STOP refuses every write: logged once, an issue after a few, gone once it works."""
    subentry_id = add_expose(hass, entry, LEVEL, WORD)
    await set_up(hass, entry)
    issue = expose_issue_id(entry, subentry_id)
    s7_smart_ha_sim.mode = "STOP"
    caplog.set_level(logging.INFO)
    for value in range(FAILURE_LIMIT):
        assert issue_registry.async_get_issue(DOMAIN, issue) is None
        hass.states.async_set(LEVEL, str(20 + value))
        await settle(hass, freezer, 2.0)
    found = issue_registry.async_get_issue(DOMAIN, issue)
    assert found is not None
    assert found.translation_placeholders is not None
    assert found.translation_placeholders["expose"] == f"{LEVEL} → VW120"
    assert "STOP" in found.translation_placeholders["error"]
    failed = [r for r in caplog.records if "cannot be written to VW120:" in r.message]
    assert len(failed) == 1
    s7_smart_ha_sim.mode = "RUN"
    hass.states.async_set(LEVEL, "30")
    await settle(hass, freezer, 2.0)
    assert s7_smart_ha_sim.get(*WORD) == 30
    assert issue_registry.async_get_issue(DOMAIN, issue) is None
    assert any("is written again" in r.message for r in caplog.records)


async def test_exposes_follow_subentry_edits(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    entry: MockConfigEntry,
    s7_smart_ha_sim: S7SmartSimulator,
) -> None:
    """An expose added to a loaded PLC starts at once; a removed one writes no more."""
    await set_up(hass, entry)
    subentry_id = add_expose(hass, entry, LEVEL, WORD, send_on_start=True)
    await settle(hass, freezer)
    assert s7_smart_ha_sim.get(*WORD) == 10
    hass.config_entries.async_remove_subentry(entry, subentry_id)
    await hass.async_block_till_done()
    hass.states.async_set(LEVEL, "15")
    await settle(hass, freezer, 2.0)
    assert s7_smart_ha_sim.get(*WORD) == 10


async def test_written_point_shows_its_value(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    entry: MockConfigEntry,
    s7_smart_ha_sim: S7SmartSimulator,
) -> None:
    """A polled point written by an expose shows the new value before the next poll."""
    add_expose(hass, entry, LEVEL, ("VW50", "signed"))
    await set_up(hass, entry)
    reads = s7_smart_ha_sim.calls["read"]
    hass.states.async_set(LEVEL, "42")
    await settle(hass, freezer)
    assert hass.states.get("sensor.s7_200_smart_level").state == "42"
    assert s7_smart_ha_sim.calls["read"] == reads  # no refresh read after an expose's write


async def test_diagnostics_list_exposes(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    entry: MockConfigEntry,
) -> None:
    """Diagnostics show each expose's settings."""
    subentry_id = add_expose(hass, entry, LEVEL, WORD, value_map="on=1;off=0")
    await set_up(hass, entry)
    result = await get_diagnostics_for_config_entry(hass, hass_client, entry)
    assert result["exposes"][subentry_id]["address"] == "VW120"
    assert result["exposes"][subentry_id]["entity_id"] == LEVEL
    assert result["exposes"][subentry_id]["value_map"] == "on=1;off=0"


async def test_export_lists_machines_only(
    hass: HomeAssistant, entry: MockConfigEntry, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """The points export names the machines, not the exposes beside them."""
    add_expose(hass, entry, LEVEL, WORD)
    await set_up(hass, entry)
    response = await hass.services.async_call(
        DOMAIN,
        "export_points",
        {"config_entry_id": entry.entry_id},
        blocking=True,
        return_response=True,
    )
    assert response is not None
    assert list(response["devices"]) == [entry.title]


async def test_edited_expose_writes_its_new_address(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    entry: MockConfigEntry,
    s7_smart_ha_sim: S7SmartSimulator,
) -> None:
    """Editing a loaded PLC's expose in its form moves its writes to the new address at once."""
    subentry_id = add_expose(hass, entry, LEVEL, WORD)
    await set_up(hass, entry)
    result = await entry.start_subentry_reconfigure_flow(hass, subentry_id)
    result = await hass.config_entries.subentries.async_configure(
        result["flow_id"], {"entity_id": LEVEL}
    )
    result = await hass.config_entries.subentries.async_configure(
        result["flow_id"], {"address": "vw130", "data_type": "signed", "send_on_start": True}
    )
    assert result["reason"] == "reconfigure_successful"
    await settle(hass, freezer)
    assert s7_smart_ha_sim.get("VW130") == 10
    hass.states.async_set(LEVEL, "11")
    await settle(hass, freezer, 2.0)
    assert s7_smart_ha_sim.get("VW130") == 11
    assert s7_smart_ha_sim.get(*WORD) == 0


async def test_follows_a_renamed_entity(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    entry: MockConfigEntry,
    s7_smart_ha_sim: S7SmartSimulator,
) -> None:
    """An entity given another id in Home Assistant keeps its expose: stored, titled, written."""
    registry = er.async_get(hass)
    outdoor = registry.async_get_or_create("sensor", "demo", "outdoor", suggested_object_id="out")
    hass.states.async_set(outdoor.entity_id, "4.5")
    subentry_id = add_expose(hass, entry, outdoor.entity_id, REAL)
    await set_up(hass, entry)
    registry.async_update_entity(outdoor.entity_id, new_entity_id="sensor.garden")
    await hass.async_block_till_done()
    subentry = entry.subentries[subentry_id]
    assert subentry.data["entity_id"] == "sensor.garden"
    assert subentry.title == "sensor.garden → VD400"
    hass.states.async_set("sensor.garden", "7.25")
    await settle(hass, freezer, 2.0)
    assert s7_smart_ha_sim.get(*REAL) == 7.25
