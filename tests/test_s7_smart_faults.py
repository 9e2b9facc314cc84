"""S7-200 SMART faults seen from Home Assistant: one busy answer or a smaller node limit costs
no entity its value (issue 19: both made every entity of the PLC unavailable)."""

from __future__ import annotations

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import ConfigEntryState
from homeassistant.core import HomeAssistant
from homeassistant.helpers import issue_registry as ir
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import DOMAIN
from simulators.s7_smart import HttpFault, S7SmartSimulator

from .ha_fixtures import make_entry, point, poll

pytestmark = pytest.mark.no_pacing

TEMPERATURE = "sensor.s7_200_smart_temperature"


@pytest.mark.parametrize("status", [500, 503, 404])
async def test_one_busy_answer_costs_no_value(
    hass: HomeAssistant,
    s7_smart_sim: S7SmartSimulator,
    setup_integration: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    status: int,
) -> None:
    s7_smart_sim.http_faults = [HttpFault(status, "<html>busy</html>")]
    await poll(hass, freezer)
    assert hass.states.get(TEMPERATURE).state == "21.5"
    assert not s7_smart_sim.http_faults


async def test_smaller_node_limit_in_other_words(
    hass: HomeAssistant,
    s7_smart_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    issue_registry: ir.IssueRegistry,
) -> None:
    """A firmware taking 10 nodes, saying "Too many nodes." under the code our old table read as
    a lost session: every entity has its value, and no session conflict is raised."""
    s7_smart_sim.max_nodes, s7_smart_sim.codes = 10, "shuffled"
    for index in range(40):
        s7_smart_sim.set(f"VW{2 * index}", index)
    words = [point(f"w{i}", f"Word {i}", "sensor", f"VW{2 * i}", "signed") for i in range(40)]
    entry = make_entry(hass, s7_smart_sim, words)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await poll(hass, freezer, times=3)
    assert hass.states.get("sensor.s7_200_smart_word_39").state == "39"
    assert entry.runtime_data.client.metrics.session_renewals == 0
    assert issue_registry.async_get_issue(DOMAIN, f"session_conflict_{entry.entry_id}") is None


async def test_deeply_nested_reply_at_setup_is_retried(
    hass: HomeAssistant, s7_smart_sim: S7SmartSimulator
) -> None:
    s7_smart_sim.http_faults = [HttpFault(200, "[" * 100_000 + "]" * 100_000)]
    entry = make_entry(hass, s7_smart_sim, [])
    await hass.config_entries.async_setup(entry.entry_id)
    assert entry.state is ConfigEntryState.SETUP_RETRY
