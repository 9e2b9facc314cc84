"""S7-200 SMART faults seen from Home Assistant: one busy answer or a smaller node limit costs
no entity its value (issue 19: both made every entity of the PLC unavailable)."""

from __future__ import annotations

import asyncio
from datetime import timedelta

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import ConfigEntryState
from homeassistant.core import HomeAssistant
from homeassistant.helpers import issue_registry as ir
from homeassistant.util import dt as dt_util
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, async_fire_time_changed

from custom_components.plc_bridge.const import DOMAIN
from custom_components.plc_bridge.plc.vendors.s7_smart import rpc
from simulators.s7_smart import HttpFault, S7SmartSimulator
from tests.entries import SCAN_INTERVAL, make_entry, point, poll

pytestmark = pytest.mark.no_pacing

TEMPERATURE = "sensor.s7_200_smart_temperature"


@pytest.mark.parametrize("times", [1, 2, 3])
@pytest.mark.parametrize("status", [500, 503, 404])
async def test_busy_answers_cost_no_value(  # noqa: PLR0917 - fixtures and parameters
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    setup_integration: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    monkeypatch: pytest.MonkeyPatch,
    status: int,
    times: int,
) -> None:
    """One busy answer (issue 19) or two or three in a row (issue 23): resent within the poll
    interval, every entity keeps its value (the first resend after 10 ms here, 1 s in use)."""
    monkeypatch.setattr(rpc, "BUSY_BACKOFF", 0.01)
    s7_smart_ha_sim.set("VD100", 22.3, "float")
    s7_smart_ha_sim.real_format = "double"
    s7_smart_ha_sim.busy, s7_smart_ha_sim.busy_status = (
        times,
        HttpFault(status, "<html>busy</html>"),
    )
    before = s7_smart_ha_sim.requests
    freezer.tick(timedelta(seconds=SCAN_INTERVAL))
    async_fire_time_changed(hass)
    for _turn in range(2000):  # the poll's back-off waits run when their time has come
        if hass.states.get(TEMPERATURE).state == "22.3":
            break
        await asyncio.sleep(0)
        async_fire_time_changed(hass, dt_util.utcnow() + timedelta(seconds=0.5))
    await hass.async_block_till_done()
    assert hass.states.get(TEMPERATURE).state == "22.3"
    assert s7_smart_ha_sim.requests - before == times + 1


async def test_smaller_node_limit_in_other_words(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    issue_registry: ir.IssueRegistry,
) -> None:
    """A firmware taking 10 nodes, saying "Too many nodes." under the code our old table read as
    a lost session: every entity has its value, and no session conflict is raised."""
    s7_smart_ha_sim.max_nodes, s7_smart_ha_sim.codes = 10, "shuffled"
    for index in range(40):
        s7_smart_ha_sim.set(f"VW{2 * index}", index)
    words = [point(f"w{i}", f"Word {i}", "sensor", f"VW{2 * i}", "signed") for i in range(40)]
    entry = make_entry(hass, s7_smart_ha_sim, words)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await poll(hass, freezer, times=3)
    assert hass.states.get("sensor.s7_200_smart_word_39").state == "39"
    assert entry.runtime_data.client.metrics.session_renewals == 0
    assert issue_registry.async_get_issue(DOMAIN, f"session_conflict_{entry.entry_id}") is None


async def test_deeply_nested_reply_at_setup_is_retried(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    s7_smart_ha_sim.http_faults = [HttpFault(200, "[" * 100_000 + "]" * 100_000)]
    entry = make_entry(hass, s7_smart_ha_sim, [])
    await hass.config_entries.async_setup(entry.entry_id)
    assert entry.state is ConfigEntryState.SETUP_RETRY
