"""Objects per point entity, RSS per point and the longest full collection: in Home Assistant.

Run by `python -m bench.objects` (pytest with the suite's fixtures); BENCH_POINTS sets the size.
"""

from __future__ import annotations

import gc
import json
import os

from freezegun.api import FrozenDateTimeFactory
from homeassistant.core import HomeAssistant

from bench.objects import (
    count_objects,
    longest_full_collection,
    machines,
    point_entities,
    rss_kib,
)
from simulators.s7_smart import S7SmartSimulator
from tests.entries import ENTRY_ID, UNIQUE_ID, add_entry, poll, sim_data

POINTS = int(os.environ.get("BENCH_POINTS", "10"))


async def test_objects(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """Set the machines up, restart them, poll, and print the figures as one BENCH line.

    An entry without machines is set up and removed first: the platforms' modules and Home
    Assistant's one-time setup are then in the RSS the points' is measured from.
    """
    empty = add_entry(
        hass,
        title="Empty",
        entry_id="01JPLCBR1DGE00000000EMPTY0",
        unique_id="plc-bridge-empty",
        data=sim_data(s7_smart_ha_sim),
    )
    assert await hass.config_entries.async_setup(empty.entry_id)
    await poll(hass, freezer)
    assert await hass.config_entries.async_remove(empty.entry_id)
    gc.collect()
    before = rss_kib()
    entry = add_entry(
        hass,
        title="S7-200 SMART",
        entry_id=ENTRY_ID,
        unique_id=UNIQUE_ID,
        data=sim_data(s7_smart_ha_sim),
        subentries=machines(POINTS),
    )
    assert await hass.config_entries.async_setup(entry.entry_id)
    await poll(hass, freezer)
    assert await hass.config_entries.async_unload(entry.entry_id)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await poll(hass, freezer, 2)
    gc.collect()
    after = rss_kib()
    shared = [entry.subentries, entry.runtime_data.coordinator.data]
    counted = count_objects(hass, point_entities(hass), shared)
    result = {
        "check": "objects",
        "points": POINTS,
        **counted,
        "rss_kib_per_point": (after - before) / POINTS,
        "gc_full_max_ms": longest_full_collection(),
        "gc_objects": len(gc.get_objects()),
    }
    print("\nBENCH " + json.dumps(result))
    assert counted["entities"] == POINTS
