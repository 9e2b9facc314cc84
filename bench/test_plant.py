"""Ten PLCs of 1,000 points in one Home Assistant: start-up, loop lag, state writes, memory.

Run by `python -m bench.plant` (pytest with the suite's fixtures, real time, asyncio debug off).
The PLCs are S7-200 SMART simulators in a subprocess (bench/plant_sims.py), so the loop lag and
the memory measured here are Home Assistant's and ours only. Settings come from BENCH_* variables.
"""

from __future__ import annotations

import asyncio
from dataclasses import dataclass, field
import gc
import json
import logging
import os
from pathlib import Path
import statistics
import sys
import time
import tracemalloc
from typing import Any

from homeassistant.const import (
    CONF_HOST,
    CONF_PASSWORD,
    CONF_PORT,
    CONF_USERNAME,
    EVENT_STATE_CHANGED,
    STATE_UNAVAILABLE,
)
from homeassistant.core import Event, HomeAssistant, callback
import pytest

from custom_components.plc_bridge.const import CONF_FINGERPRINT, CONF_OPTIONS, CONF_TLS, CONF_VENDOR
from custom_components.plc_bridge.coordinator import PlcCoordinator
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from tests.entries import add_entry, device, point

PLCS = int(os.environ.get("BENCH_PLCS", "10"))
POINTS = int(os.environ.get("BENCH_POINTS", "1000"))
DEVICES = 10
MINUTES = float(os.environ.get("BENCH_MINUTES", "3"))
CHANGING = int(os.environ.get("BENCH_CHANGING", "1000"))
PERIOD = float(os.environ.get("BENCH_PERIOD", "5"))
PACING = float(os.environ.get("BENCH_PACING", "1.0"))
TRACE = os.environ.get("BENCH_TRACE", "") == "1"
FAULT = float(os.environ.get("BENCH_FAULT", "0"))
STALL = 0.25
TICK = 0.02
ROOT = Path(__file__).resolve().parent.parent
OURS = str(ROOT / "custom_components")


def rss_mib() -> float:
    """The resident set size of this process, in MiB."""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return float("nan")


@dataclass
class Probe:
    """What the run records: loop lag, GC pauses, the time our listener dispatch holds the loop."""

    lags: list[tuple[float, float]] = field(default_factory=list)  # (woke at, lag s)
    gcs: list[tuple[float, float, int]] = field(default_factory=list)  # (start, s, generation)
    dispatches: list[tuple[float, float]] = field(default_factory=list)  # (start, s)
    full_cpu: list[tuple[float, float]] = field(default_factory=list)  # (start, CPU s), gen 2
    _gc_start: float = 0.0
    _gc_cpu: float = 0.0

    def on_gc(self, phase: str, info: dict[str, Any]) -> None:
        """gc.callbacks hook: time every collection (full ones in CPU time too)."""
        now, cpu = time.perf_counter(), time.thread_time()
        if phase == "start":
            self._gc_start, self._gc_cpu = now, cpu
        else:
            self.gcs.append((self._gc_start, now - self._gc_start, int(info["generation"])))
            if info["generation"] == 2:
                self.full_cpu.append((self._gc_start, cpu - self._gc_cpu))

    async def watch_loop(self, stop: asyncio.Event) -> None:
        """Sleep TICK at a time; how late each wake-up is, is the loop's lag."""
        while not stop.is_set():
            asked = time.perf_counter()
            await asyncio.sleep(TICK)
            woke = time.perf_counter()
            self.lags.append((woke, max(0.0, woke - asked - TICK)))

    def gc_inside(self, begin: float, length: float) -> float:
        """Seconds of garbage collection within [begin, begin + length]."""
        end = begin + length
        return sum(
            min(end, start + took) - max(begin, start)
            for start, took, _generation in self.gcs
            if start < end and start + took > begin
        )

    def stalls(self, since: float) -> list[dict[str, Any]]:
        """Every lag >= STALL after `since`, with the GC pauses and dispatches inside it."""
        found = []
        for woke, lag in self.lags:
            if woke < since or lag < STALL:
                continue
            start = woke - lag - TICK

            def inside(
                begin: float, length: float, start: float = start, woke: float = woke
            ) -> bool:
                return begin < woke and begin + length > start

            found.append(
                {
                    "lag_ms": round(lag * 1000),
                    "at_s": round(woke - since),
                    "gc_ms": round(sum(s for b, s, _g in self.gcs if inside(b, s)) * 1000),
                    "ours_ms": round(sum(s for b, s in self.dispatches if inside(b, s)) * 1000),
                }
            )
        return found


def entry_data(info: dict[str, Any]) -> dict[str, Any]:
    """The entry data of one simulated PLC."""
    return {
        CONF_VENDOR: "s7_smart",
        CONF_HOST: info["host"],
        CONF_PORT: info["port"],
        CONF_USERNAME: info["username"],
        CONF_PASSWORD: info["password"],
        CONF_TLS: "pin",
        CONF_FINGERPRINT: info["fingerprint"],
        CONF_OPTIONS: {},
    }


def plant(hass: HomeAssistant, infos: list[dict[str, Any]]) -> list[Any]:
    """Add PLCS entries of POINTS word sensors in DEVICES devices each (not set up)."""
    per = POINTS // DEVICES
    entries = []
    for n, info in enumerate(infos):
        devices = [
            device(
                [
                    point(f"d{d}p{i}", f"Word {i}", "sensor", f"VW{2 * (per * d + i)}", "signed")
                    for i in range(per)
                ],
                subentry_id=f"plc{n}dev{d}",
                title=f"PLC {n} machine {d}",
            )
            for d in range(DEVICES)
        ]
        entries.append(
            add_entry(
                hass,
                title=f"PLC {n}",
                entry_id=f"plantplc{n:02d}",
                unique_id=f"plant-plc-{n}",
                data=entry_data(info),
                subentries=devices,
            )
        )
    return entries


def forced_collections(times: int = 7) -> list[float]:
    """Run full collections at the end, each timed in this thread's CPU time (s), sorted.

    The plant's own full collections are few in a run and the loop's clock counts what other
    processes take: these compare two runs' collections of the same plant.
    """
    times_s = []
    for _ in range(times):
        used = time.thread_time()
        gc.collect()
        times_s.append(time.thread_time() - used)
    return sorted(times_s)


def percentile(values: list[float], share: float) -> float:
    """The value below which `share` of the values lie (0 for none)."""
    if not values:
        return 0.0
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(share * len(ordered)))]


def ours_in(snapshot_diff: list[tracemalloc.StatisticDiff]) -> list[dict[str, Any]]:
    """The largest growths by line, ours marked."""
    rows = []
    for stat in snapshot_diff[:12]:
        frame = stat.traceback[0]
        rows.append(
            {
                "where": f"{frame.filename.removeprefix(str(ROOT) + '/')}:{frame.lineno}",
                "kib": round(stat.size_diff / 1024, 1),
                "count": stat.count_diff,
                "ours": frame.filename.startswith(OURS),
            }
        )
    return rows


async def start_simulators() -> tuple[asyncio.subprocess.Process, list[dict[str, Any]]]:
    """Start the simulators' process and read where each PLC listens."""
    process = await asyncio.create_subprocess_exec(
        *(sys.executable, "-m", "bench.plant_sims", str(PLCS), str(CHANGING), str(PERIOD)),
        str(FAULT),
        cwd=ROOT,
        stdin=asyncio.subprocess.PIPE,
        stdout=asyncio.subprocess.PIPE,
    )
    assert process.stdout is not None
    infos = [json.loads(await process.stdout.readline()) for _ in range(PLCS)]
    return process, infos


async def test_plant(
    hass: HomeAssistant, hass_storage: dict[str, Any], monkeypatch: pytest.MonkeyPatch
) -> None:
    """Set the plant up, poll it for MINUTES, print the figures as one BENCH line.

    What the harness keeps of the files Home Assistant writes (`hass_storage`: each parsed, the
    entity registry's a dict per entity) is dropped before each measure: a real Home Assistant
    writes them to disk.
    """
    loop = asyncio.get_running_loop()
    loop.set_debug(False)  # the test harness's debug mode costs more than what is measured
    # As Home Assistant logs by default: the harness's DEBUG records would cost more still.
    for name in ("", "homeassistant", "custom_components", "asyncio", "aiohttp"):
        monkeypatch.setattr(logging.getLogger(name), "level", logging.WARNING)
    monkeypatch.setattr(S7SmartClient, "request_interval", PACING)
    process, infos = await start_simulators()
    entries = plant(hass, infos)
    probe = Probe()
    gc.callbacks.append(probe.on_gc)
    # Each call of `_update` (where polls update entities in slices) holds the loop on its own.
    held = "_update" if hasattr(PlcCoordinator, "_update") else "async_update_listeners"
    original = getattr(PlcCoordinator, held)
    polls = [0]

    def timed(coordinator: PlcCoordinator, *args: Any) -> None:
        started = time.perf_counter()
        original(coordinator, *args)
        probe.dispatches.append((started, time.perf_counter() - started))

    monkeypatch.setattr(PlcCoordinator, held, timed)
    listeners = PlcCoordinator.async_update_listeners

    def counted(coordinator: PlcCoordinator) -> None:
        if time.perf_counter() >= steady_at[0]:
            polls[0] += 1
        listeners(coordinator)

    monkeypatch.setattr(PlcCoordinator, "async_update_listeners", counted)
    steady_at = [float("inf")]
    changes = [0]

    @callback
    def count(_event: Event) -> None:
        changes[0] += 1

    unsubscribe = hass.bus.async_listen(EVENT_STATE_CHANGED, count)
    stop = asyncio.Event()
    watcher = loop.create_task(probe.watch_loop(stop))
    total = PLCS * POINTS
    hass_storage.clear()
    gc.collect()
    rss_before = rss_mib()
    tracked_before = len(gc.get_objects())
    # The first start registers every entity; the second is what every restart looks like.
    started = time.perf_counter()
    await asyncio.gather(*(hass.config_entries.async_setup(e.entry_id) for e in entries))
    first_setup_s = time.perf_counter() - started
    for entry in entries:
        await hass.config_entries.async_unload(entry.entry_id)
    started = time.perf_counter()
    await asyncio.gather(*(hass.config_entries.async_setup(e.entry_id) for e in entries))
    setup_s = time.perf_counter() - started
    registered_s = available_s = None
    while time.perf_counter() - started < 90:  # with faults, some PLC may be away: go on
        states = [s for s in hass.states.async_all("sensor") if "_machine_" in s.entity_id]
        if registered_s is None and len(states) == total:
            registered_s = time.perf_counter() - started
        if sum(s.state != STATE_UNAVAILABLE for s in states) == total:
            available_s = time.perf_counter() - started
            break
        await asyncio.sleep(0.5)
    steady = steady_at[0] = time.perf_counter()
    hass_storage.clear()
    rss = [(0.0, rss_mib())]
    if TRACE:
        tracemalloc.start(1)
    first: tracemalloc.Snapshot | None = None
    changes_before = changes[0]
    while (elapsed := time.perf_counter() - steady) < MINUTES * 60:
        await asyncio.sleep(min(10.0, MINUTES * 60 - elapsed))
        hass_storage.clear()
        rss.append((round(time.perf_counter() - steady), rss_mib()))
        # Compared from a third of the run on: what replaces objects traced since nets out.
        if TRACE and first is None and elapsed >= MINUTES * 20:
            first = tracemalloc.take_snapshot()
    growth = []
    if first is not None:
        growth = ours_in(tracemalloc.take_snapshot().compare_to(first, "lineno"))
        tracemalloc.stop()
    stop.set()
    await watcher
    unsubscribe()
    gc.callbacks.remove(probe.on_gc)
    forced = forced_collections()
    tracked = len(gc.get_objects())
    steady_lags = [lag for woke, lag in probe.lags if woke >= steady]
    holds = [s for b, s in probe.dispatches if b >= steady]
    # The part of each hold that is no garbage collection (one may start inside our writes).
    own = [s - probe.gc_inside(b, s) for b, s in probe.dispatches if b >= steady]
    gen2 = [s for b, s, g in probe.gcs if b >= steady and g == 2]
    stalls = probe.stalls(steady)
    result = {
        "check": "plant",
        "plcs": PLCS,
        "points": POINTS,
        "changing_per_plc": CHANGING,
        "pacing_s": PACING,
        "fault_s": FAULT,
        "minutes": MINUTES,
        "first_setup_returned_s": round(first_setup_s, 2),
        "setup_returned_s": round(setup_s, 2),
        "all_registered_s": None if registered_s is None else round(registered_s, 2),
        "all_available_s": None if available_s is None else round(available_s, 2),
        "polls": polls[0],
        "holds": len(holds),
        "state_changes": changes[0] - changes_before,
        "lag_max_ms": round(max(steady_lags, default=0) * 1000, 1),
        "lag_p99_ms": round(percentile(steady_lags, 0.99) * 1000, 1),
        "stalls": stalls,
        "hold_max_ms": round(max(holds, default=0) * 1000, 1),
        "hold_max_without_gc_ms": round(max(own, default=0) * 1000, 1),
        "hold_median_ms": round(statistics.median(holds) * 1000, 1) if holds else 0,
        "gc_gen2": len(gen2),
        "gc_gen2_max_ms": round(max(gen2, default=0) * 1000, 1),
        "gc_gen2_max_cpu_ms": round(
            max((s for b, s in probe.full_cpu if b >= steady), default=0) * 1000, 1
        ),
        "rss_mib": [(t, round(m, 1)) for t, m in rss],
        "rss_before_setup_mib": round(rss_before, 1),
        "gc_forced_cpu_ms": [round(cpu * 1000, 1) for cpu in forced],
        "gc_tracked": tracked,
        "gc_tracked_before_setup": tracked_before,
        "growth": growth,
    }
    print("\nBENCH " + json.dumps(result))
    for entry in entries:
        await hass.config_entries.async_unload(entry.entry_id)
    assert process.stdin is not None
    process.stdin.close()
    await process.wait()
