"""Exposes whose values or writes fail, on the S7-200 SMART: issues kept across reloads, retries."""

from __future__ import annotations

import asyncio
from datetime import timedelta
import math
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import ConfigEntryState
from homeassistant.const import STATE_UNAVAILABLE
from homeassistant.core import CoreState, HomeAssistant
from homeassistant.helpers import issue_registry as ir
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, async_fire_time_changed

from custom_components.plc_bridge.const import DOMAIN
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from custom_components.plc_bridge.runtime.expose import BATCH_WINDOW, FAILURE_LIMIT, RETRY_INTERVAL
from custom_components.plc_bridge.runtime.issues import expose_issue_id
from simulators.s7_smart import S7SmartSimulator
from tests.entries import make_entry, point, set_up
from tests.harness import add_expose, settle

pytestmark = pytest.mark.no_pacing

LEVEL = "input_number.level"
WORD = ("VW120", "signed")


@pytest.fixture
def entry(hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator) -> MockConfigEntry:
    """An S7-200 SMART entry with one polled point (not set up), and the level exposed."""
    hass.states.async_set(LEVEL, "10")
    return make_entry(hass, s7_smart_ha_sim, [point("level", "Level", "sensor", "VW50", "signed")])


async def fail_until_issue(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    sim: S7SmartSimulator,
    issues: ir.IssueRegistry,
    issue: str,
) -> None:
    """Put the CPU in STOP and change the level until the expose's issue is raised."""
    sim.mode = "STOP"
    for value in range(FAILURE_LIMIT):
        hass.states.async_set(LEVEL, str(20 + value))
        await settle(hass, freezer, 2.0)
    assert issues.async_get_issue(DOMAIN, issue) is not None


@pytest.mark.parametrize("change", ["reload", "edit"])
async def test_issue_from_before_a_reload_or_edit_cleared_on_success(  # noqa: PLR0917
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    entry: MockConfigEntry,
    s7_smart_ha_sim: S7SmartSimulator,
    issue_registry: ir.IssueRegistry,
    change: str,
) -> None:
    """An issue raised before the entry reloads (or the expose is edited) goes at the next write
    that works: the expose running now knows of it."""
    subentry_id = add_expose(hass, entry, LEVEL, WORD)
    await set_up(hass, entry)
    issue = expose_issue_id(entry, subentry_id)
    await fail_until_issue(hass, freezer, s7_smart_ha_sim, issue_registry, issue)
    if change == "reload":
        assert await hass.config_entries.async_reload(entry.entry_id)
    else:
        subentry = entry.subentries[subentry_id]
        hass.config_entries.async_update_subentry(
            entry, subentry, data={**subentry.data, "cooldown": 2.0}
        )
    await settle(hass, freezer, 5.0)
    assert issue_registry.async_get_issue(DOMAIN, issue) is not None  # still failing
    s7_smart_ha_sim.mode = "RUN"
    hass.states.async_set(LEVEL, "30")
    await settle(hass, freezer, 5.0)
    assert s7_smart_ha_sim.get(*WORD) == 30
    assert issue_registry.async_get_issue(DOMAIN, issue) is None


async def test_failed_value_written_again_until_it_lands(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    entry: MockConfigEntry,
    s7_smart_ha_sim: S7SmartSimulator,
    issue_registry: ir.IssueRegistry,
) -> None:
    """A value the PLC did not take is not lost: with no further change of the entity it is
    written again every RETRY_INTERVAL (one request), raising the issue if that keeps failing,
    until the PLC takes it; then nothing more is sent."""
    subentry_id = add_expose(hass, entry, LEVEL, WORD)
    await set_up(hass, entry)
    s7_smart_ha_sim.mode = "STOP"
    hass.states.async_set(LEVEL, "25")
    await settle(hass, freezer)
    for _ in range(FAILURE_LIMIT - 1):
        writes = s7_smart_ha_sim.calls["write"]
        await settle(hass, freezer, RETRY_INTERVAL)
        assert s7_smart_ha_sim.calls["write"] == writes + 1
    assert issue_registry.async_get_issue(DOMAIN, expose_issue_id(entry, subentry_id))
    s7_smart_ha_sim.mode = "RUN"
    await settle(hass, freezer, RETRY_INTERVAL)
    assert s7_smart_ha_sim.get(*WORD) == 25
    assert issue_registry.async_get_issue(DOMAIN, expose_issue_id(entry, subentry_id)) is None
    writes = s7_smart_ha_sim.calls["write"]
    for _ in range(3):
        await settle(hass, freezer, RETRY_INTERVAL)
    assert s7_smart_ha_sim.calls["write"] == writes


async def test_refused_value_leaves_no_older_one_to_write(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    entry: MockConfigEntry,
    s7_smart_ha_sim: S7SmartSimulator,
) -> None:
    """After a state the address cannot hold, the value before it is neither written when the
    cooldown ends nor resent: the PLC never gets a value the entity no longer has."""
    add_expose(hass, entry, LEVEL, WORD, scale=1000.0, cooldown=5.0, resend=30.0)
    await set_up(hass, entry)
    hass.states.async_set(LEVEL, "11")
    await settle(hass, freezer)
    assert s7_smart_ha_sim.get(*WORD) == 11000
    hass.states.async_set(LEVEL, "12")  # within the cooldown: waits for its end
    hass.states.async_set(LEVEL, "40")  # 40000: refused
    await settle(hass, freezer, 5.0)
    assert s7_smart_ha_sim.get(*WORD) == 11000
    s7_smart_ha_sim.set(WORD[0], 99)
    await settle(hass, freezer, 30.0)
    assert s7_smart_ha_sim.get(*WORD) == 99
    hass.states.async_set(LEVEL, "13")
    await settle(hass, freezer, 5.0)
    assert s7_smart_ha_sim.get(*WORD) == 13000


async def test_nothing_written_while_home_assistant_stops(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    entry: MockConfigEntry,
    s7_smart_ha_sim: S7SmartSimulator,
) -> None:
    """An entity its integration marks unavailable as Home Assistant stops does not write the
    expose's default: pending writes are dropped at the stop, and so are those it brings."""
    add_expose(hass, entry, LEVEL, WORD, default="7", cooldown=0.0)
    await set_up(hass, entry)
    writes = s7_smart_ha_sim.calls["write"]
    hass.set_state(CoreState.stopping)
    try:
        hass.states.async_set(LEVEL, STATE_UNAVAILABLE)
        await settle(hass, freezer, 1.0)
    finally:
        hass.set_state(CoreState.running)
    assert s7_smart_ha_sim.calls["write"] == writes
    assert s7_smart_ha_sim.get(*WORD) == 0


async def test_expose_to_a_point_made_read_only_fails_alone(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    s7_smart_ha_sim: S7SmartSimulator,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """A point marked read only after an expose to its address was set up: that expose is
    refused before sending, logged; the other exposes of the same batch are written."""
    hass.states.async_set(LEVEL, "10")
    hass.states.async_set("input_number.other", "10")
    guarded = point("guarded", "Guarded", "sensor", WORD[0], WORD[1], read_only=True)
    entry = make_entry(hass, s7_smart_ha_sim, [guarded])
    add_expose(hass, entry, LEVEL, WORD)
    add_expose(hass, entry, "input_number.other", ("VW122", "signed"))
    await set_up(hass, entry)
    hass.states.async_set(LEVEL, "11")
    hass.states.async_set("input_number.other", "12")
    await settle(hass, freezer)
    assert s7_smart_ha_sim.get("VW122") == 12
    assert s7_smart_ha_sim.get(*WORD) == 0
    assert any("cannot be written to VW120" in r.message for r in caplog.records)


@pytest.mark.parametrize("bad", [{"cooldown": "soon"}, {"resend": math.inf}])
async def test_expose_with_unreadable_settings_skipped(  # noqa: PLR0917
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    entry: MockConfigEntry,
    s7_smart_ha_sim: S7SmartSimulator,
    caplog: pytest.LogCaptureFixture,
    bad: dict[str, Any],
) -> None:
    """An expose whose stored settings cannot be read (a hand-edited file pasted: a cooldown
    that is no number, a resend `.inf`, an address the parser refuses) is left out or sends
    nothing, logged once; the PLC and its other exposes work."""
    add_expose(hass, entry, "input_number.other", ("VW122", "signed"), **bad)
    add_expose(hass, entry, "input_number.third", ("VX1", "signed"))
    add_expose(hass, entry, LEVEL, WORD)
    await set_up(hass, entry)
    assert entry.state is ConfigEntryState.LOADED
    for value in ("11", "12"):
        for entity_id in (LEVEL, "input_number.other", "input_number.third"):
            hass.states.async_set(entity_id, value)
        await settle(hass, freezer, 2.0)
    assert s7_smart_ha_sim.get(*WORD) == 12
    assert s7_smart_ha_sim.get("VW122") == 0
    assert [r.levelname for r in caplog.records if "input_number.other → VW122" in r.message] == [
        "WARNING"
    ]
    assert [r.levelname for r in caplog.records if "VX1" in r.message] == ["WARNING"]


async def test_expose_removed_while_its_write_fails_raises_no_issue(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    entry: MockConfigEntry,
    s7_smart_ha_sim: S7SmartSimulator,
    issue_registry: ir.IssueRegistry,
) -> None:
    """An expose deleted while its last write is on the way: the write's failure raises no
    issue for it (nothing could ever clear that one)."""
    subentry_id = add_expose(hass, entry, LEVEL, WORD, cooldown=0.0)
    await set_up(hass, entry)
    s7_smart_ha_sim.mode = "STOP"
    for value in range(FAILURE_LIMIT - 1):
        hass.states.async_set(LEVEL, str(20 + value))
        await settle(hass, freezer)
    hass.states.async_set(LEVEL, "30")
    await hass.async_block_till_done()
    freezer.tick(timedelta(seconds=BATCH_WINDOW))
    async_fire_time_changed(hass)  # the batch is written: its request is on the way
    hass.config_entries.async_remove_subentry(entry, subentry_id)
    await hass.async_block_till_done(wait_background_tasks=True)
    assert s7_smart_ha_sim.calls["write"] == FAILURE_LIMIT
    assert issue_registry.async_get_issue(DOMAIN, expose_issue_id(entry, subentry_id)) is None


async def test_user_without_write_permission_sends_nothing(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    entry: MockConfigEntry,
    s7_smart_ha_sim: S7SmartSimulator,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """A PLC user that may not write: an expose's writes (and their retries) are refused before
    any request, once in the log, in the words an entity's write gets."""
    s7_smart_ha_sim.write_permission = False
    add_expose(hass, entry, LEVEL, WORD)
    await set_up(hass, entry)
    hass.states.async_set(LEVEL, "11")
    await settle(hass, freezer)
    await settle(hass, freezer, 3 * RETRY_INTERVAL)
    assert s7_smart_ha_sim.calls.get("write", 0) == 0
    refused = [r.message for r in caplog.records if "cannot be written to VW120:" in r.message]
    assert len(refused) == 1
    assert "may not write; nothing was sent" in refused[0]


async def test_newer_value_not_overtaken_by_an_older_write(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    entry: MockConfigEntry,
    s7_smart_ha_sim: S7SmartSimulator,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A burst of 20 to a firmware taking 8 nodes, its limit unknown: while the write learns it
    (several requests), one expose changes three times. Its latest value is written after the
    older one is sent again in smaller requests, never before, and in one write, not three:
    the PLC ends with the latest value."""
    s7_smart_ha_sim.max_nodes = 8
    entities = [f"input_number.level_{index}" for index in range(20)]
    targets = [(f"VW{300 + 2 * index}", "signed") for index in range(20)]
    for entity_id, target in zip(entities, targets, strict=True):
        hass.states.async_set(entity_id, "0")
        add_expose(hass, entry, entity_id, target, cooldown=0.0)
    await set_up(hass, entry)
    learning = S7SmartClient._fewer_write_nodes

    async def changed_meanwhile(client: S7SmartClient, group: Any) -> bool:
        """Change the last entity; let each value's write go (if it may) before learning."""
        for value in ("97", "98", "99"):
            before = s7_smart_ha_sim.calls["write"]
            hass.states.async_set(entities[-1], value)
            await hass.async_block_till_done()
            freezer.tick(timedelta(seconds=BATCH_WINDOW))
            async_fire_time_changed(hass)
            for _ in range(1000):
                if s7_smart_ha_sim.calls["write"] > before:
                    break
                await asyncio.sleep(0)
        return await learning(client, group)

    monkeypatch.setattr(S7SmartClient, "_fewer_write_nodes", changed_meanwhile)
    writes = s7_smart_ha_sim.calls["write"]
    for index, entity_id in enumerate(entities):
        hass.states.async_set(entity_id, str(index + 11))
    await settle(hass, freezer)
    await settle(hass, freezer)
    assert [s7_smart_ha_sim.get(address) for address, _ in targets[:-1]] == list(range(11, 30))
    assert s7_smart_ha_sim.get(targets[-1][0]) == 99
    assert s7_smart_ha_sim.calls["write"] - writes == 1 + 3 + 1  # refused, 8 + 8 + 4, then 99
