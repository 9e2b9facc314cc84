"""Objects per point entity, RSS per point and the longest full collection: in Home Assistant.

Run by `python -m bench.objects` (pytest with the suite's fixtures); BENCH_POINTS sets the size.
"""

from __future__ import annotations

import gc
import json
import os
import tracemalloc
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.core import HomeAssistant

from bench.objects import (
    allocated_by,
    count_objects,
    count_owners,
    longest_full_collection,
    machines,
    point_entities,
    rss_kib,
    tracked_types,
)
from simulators.s7_smart import S7SmartSimulator
from tests.entries import ENTRY_ID, UNIQUE_ID, add_entry, poll, sim_data

POINTS = int(os.environ.get("BENCH_POINTS", "10"))
TRACE = os.environ.get("BENCH_TRACE", "") == "1"
"""Trace allocations (by module); RSS and collection times then include tracemalloc's cost."""


async def test_objects(
    hass: HomeAssistant,
    hass_storage: dict[str, Any],
    freezer: FrozenDateTimeFactory,
    s7_smart_ha_sim: S7SmartSimulator,
) -> None:
    """Set the machines up, restart them, poll, and print the figures as one BENCH line.

    An entry without machines is set up and removed first: the platforms' modules and Home
    Assistant's one-time setup are then in the RSS the points' is measured from. What the
    harness keeps of the files Home Assistant writes (`hass_storage`: each file parsed, the
    entity registry's a dict per entity) is dropped before measuring: a real Home Assistant
    writes them to disk.
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
    tracked_before = tracked_types()
    if TRACE:
        tracemalloc.start(30)
        traced = tracemalloc.take_snapshot()
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
    hass_storage.clear()
    gc.collect()
    after = rss_kib()
    tracked = tracked_types() - tracked_before
    allocated = []
    if TRACE:
        allocated = allocated_by(traced, tracemalloc.take_snapshot(), POINTS)
        tracemalloc.stop()
    coordinator = entry.runtime_data.coordinator
    shared = [entry.subentries, coordinator.data]
    counted = count_objects(hass, point_entities(hass), shared)
    wall, cpu = longest_full_collection()
    result = {
        "check": "objects",
        "points": POINTS,
        **counted,
        "owners": count_owners(hass, point_entities(hass), [coordinator], shared),
        "allocated_by": allocated,
        "tracked_per_point": round(tracked.total() / POINTS, 1),
        "tracked_types_per_point": {
            name: round(count / POINTS, 2) for name, count in tracked.most_common(16)
        },
        "rss_kib_per_point": (after - before) / POINTS,
        "gc_full_max_ms": wall,
        "gc_full_max_cpu_ms": cpu,
        "gc_objects": len(gc.get_objects()),
    }
    print("\nBENCH " + json.dumps(result))
    assert counted["entities"] == POINTS
