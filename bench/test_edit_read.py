"""The Home Assistant part of `python -m bench.edit_read`: an import's values on a paced PLC.

Run in Home Assistant's test harness in real time (no frozen clock: the pacing is the point):
one S7-200 SMART simulator, a PLC entry of a few points polled at the vendor's pacing; then a
save adds POINTS word sensors (an import). It measures one paced read of those points, the time
from the save until every new sensor shows its value, and how long after each read request's
reply its values are shown. Sizes come from the environment (BENCH_EDIT_*).
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import logging
import os
import time
from typing import Any

from homeassistant.const import EVENT_STATE_CHANGED, STATE_UNAVAILABLE, STATE_UNKNOWN
from homeassistant.core import Event, EventStateChangedData, HomeAssistant, callback
import pytest

from custom_components.plc_bridge.const import CONF_POINTS
from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from simulators.s7_smart import S7SmartSimulator
from tests.entries import DEVICE_ID, PointData, make_entry, point, set_points

POINTS = int(os.environ.get("BENCH_EDIT_POINTS", "1000"))
PACING = float(os.environ.get("BENCH_EDIT_PACING", "1.0"))
KEPT = 8
"""Points the PLC has before the import (a machine already set up)."""
FIRST = 100
"""Word index of the first imported point (after the kept ones)."""


def words(count: int, first: int) -> list[PointData]:
    """Return `count` word sensors from VW(2 * first)."""
    return [
        point(f"word{i}", f"Word {i}", "sensor", f"VW{2 * i}", "signed")
        for i in range(first, first + count)
    ]


async def test_edit_read(hass: HomeAssistant, monkeypatch: pytest.MonkeyPatch) -> None:
    """Import POINTS points into a paced PLC; print when their values are shown (a BENCH line)."""
    asyncio.get_running_loop().set_debug(False)  # the harness's debug mode costs more than this
    for name in ("", "homeassistant", "custom_components", "asyncio", "aiohttp"):
        monkeypatch.setattr(logging.getLogger(name), "level", logging.WARNING)
    monkeypatch.setattr(S7SmartClient, "request_interval", PACING)
    sim = S7SmartSimulator()
    for index in range(FIRST, FIRST + POINTS):
        sim.set(f"VW{2 * index}", 1 + index % 1000)
    await sim.start()
    replies: list[float] = []

    def noted(reply: dict[str, Any]) -> dict[str, Any]:
        if isinstance(reply.get("result", {}).get("data"), list):
            replies.append(time.perf_counter())
        return reply

    sim.rewrite = noted
    entry = make_entry(hass, sim, words(KEPT, 0))
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    client = entry.runtime_data.client
    imported = [Point(f"VW{2 * i}", "signed") for i in range(FIRST, FIRST + POINTS)]
    started = time.perf_counter()
    await client.read(imported, poll=False)
    paced_read_s = time.perf_counter() - started
    requests = client.requests_for(imported)
    await asyncio.sleep(PACING)  # the poll's pacing after that read

    shown: dict[str, float] = {}
    all_shown = asyncio.Event()
    wanted = {f"sensor.s7_200_smart_word_{i}" for i in range(FIRST, FIRST + POINTS)}

    @callback
    def note(event: Event[EventStateChangedData]) -> None:
        entity_id = event.data["entity_id"]
        state = event.data["new_state"]
        if entity_id not in wanted or entity_id in shown or state is None:
            return
        if state.state not in (STATE_UNAVAILABLE, STATE_UNKNOWN):
            shown[entity_id] = time.perf_counter()
            if len(shown) == POINTS:
                all_shown.set()

    unsubscribe = hass.bus.async_listen(EVENT_STATE_CHANGED, note)
    reads_before = sim.calls["read"]
    replies.clear()
    saved = time.perf_counter()
    points = dict(entry.subentries[DEVICE_ID].data[CONF_POINTS]) | dict(words(POINTS, FIRST))
    set_points(hass, entry, points)
    with contextlib.suppress(TimeoutError):
        await asyncio.wait_for(all_shown.wait(), 4 * paced_read_s + 30)
    reads = sim.calls["read"] - reads_before
    unsubscribe()
    times = sorted(shown.values())
    # Each value's lag: from the reply that brought it (the last one before it was shown).
    lags = [t - max((r for r in replies if r <= t), default=saved) for t in times]
    result = {
        "check": "edit_read",
        "points": POINTS,
        "kept_points": KEPT,
        "pacing_s": PACING,
        "requests": requests,
        "paced_read_s": round(paced_read_s, 2),
        "shown": len(shown),
        "all_shown_s": round(times[-1] - saved, 2) if len(times) == POINTS else None,
        "first_shown_s": round(times[0] - saved, 2) if times else None,
        "first_request_lag_s": round(lags[0], 3) if lags else None,
        "max_lag_s": round(max(lags), 3) if lags else None,
        "reads_after_save": reads,
    }
    print("\nBENCH " + json.dumps(result))
    await hass.config_entries.async_unload(entry.entry_id)
    await sim.stop()
    assert result["all_shown_s"] is not None
