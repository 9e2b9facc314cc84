"""A poll where nothing changed must not write entity state: measured in a real Home Assistant.

Run by `scripts/bench` (pytest with the test suite's fixtures): N sensor points on the S7-200
SMART simulator, a first poll, then polls with every value unchanged. It counts the state_changed
events of the point entities (what the recorder stores and automations see) and the calls of
`async_write_ha_state` (the work Home Assistant does to find out that nothing changed).
"""

from __future__ import annotations

import json
import os
from unittest.mock import patch

from freezegun.api import FrozenDateTimeFactory
from homeassistant.const import EVENT_STATE_CHANGED
from homeassistant.core import Event, HomeAssistant, callback
from homeassistant.helpers import entity_registry as er
from homeassistant.helpers.entity import Entity

from custom_components.plc_bridge.const import DOMAIN
from simulators.s7_smart import S7SmartSimulator
from tests.entries import make_entry, point, poll

POINTS = int(os.environ.get("BENCH_QUIET_POINTS", "100"))
POLLS = 3


async def test_quiet_poll(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """Unchanged values: no state_changed event; count the state writes Home Assistant does."""
    points = [point(f"p{i}", f"Point {i}", "sensor", f"VD{4 * i}", "float") for i in range(POINTS)]
    entry = make_entry(hass, s7_smart_ha_sim, points)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    registry = er.async_get(hass)
    ours = {
        e.entity_id
        for e in er.async_entries_for_config_entry(registry, entry.entry_id)
        if e.config_subentry_id is not None
    }
    assert len(ours) == POINTS
    await poll(hass, freezer)  # the first poll after setup may still fill in values

    changed: list[str] = []

    @callback
    def count(event: Event) -> None:
        if event.data["entity_id"] in ours:
            changed.append(event.data["entity_id"])

    writes: list[str] = []
    original = Entity.async_write_ha_state

    def counting_write(entity: Entity) -> None:
        if entity.entity_id in ours:
            writes.append(entity.entity_id)
        original(entity)

    unsubscribe = hass.bus.async_listen(EVENT_STATE_CHANGED, count)
    with patch.object(Entity, "async_write_ha_state", counting_write):
        await poll(hass, freezer, POLLS)
    unsubscribe()
    requests = s7_smart_ha_sim.requests
    result = {
        "check": "quiet_poll",
        "vendor": "s7_smart",
        "points": POINTS,
        "polls": POLLS,
        "state_changed": len(changed),
        "state_writes": len(writes),
        "requests_total": requests,
    }
    print("\nBENCH " + json.dumps(result))
    assert hass.config_entries.async_entries(DOMAIN)
    assert not changed, f"{len(changed)} state_changed events after polls with nothing changed"
