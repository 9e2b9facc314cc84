"""Poll classes: requests a PLC answers in a minute, a mixed set against everything read fast.

Run it alone as `python -m bench.poll_classes [--points N ...]`; `scripts/bench` prints its lines
too. The points are the main benchmark's, every tenth fast, then six normal and three slow
(10 % fast, 60 % normal, 30 % slow, spread over the PLC's memory). The minute is virtual: the
coordinator's own `PollSchedule` decides, for each of the 60 one-second ticks, which points the
tick reads, and the client reads them in one call at once, without waiting a second. Requests
are counted at the simulator in the second minute (pacing off, as in the main table). The
comparison polls every point at the fast interval: what one interval per PLC costs for a fast
limit switch.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import sys
from typing import Any

from custom_components.plc_bridge.model.poll_classes import (
    DEFAULT_FAST_INTERVAL,
    DEFAULT_SLOW_INTERVAL,
    FAST,
    NORMAL,
    SLOW,
)
from custom_components.plc_bridge.plc import PlcClient, Point
from custom_components.plc_bridge.plc.vendors import client_class
from custom_components.plc_bridge.runtime.polling import PollSchedule

from .poll import VENDORS, Simulator, make_client, ready_vendors

MINUTE = 60.0
CLASS_OF_TENTH = (FAST, NORMAL, NORMAL, NORMAL, NORMAL, NORMAL, NORMAL, SLOW, SLOW, SLOW)
"""The class of each point by its index's last digit: 10 % fast, 60 % normal, 30 % slow."""


def mixed(points: list[Point]) -> dict[Point, str]:
    """Return the points' classes: every tenth fast, then six normal and three slow."""
    return {point: CLASS_OF_TENTH[index % 10] for index, point in enumerate(points)}


async def a_minute(
    client: PlcClient, simulator: Simulator, points: list[Point], schedule: PollSchedule
) -> tuple[int, int, int]:
    """Poll for two virtual minutes as the schedule says; the second's requests, polls, points.

    The first minute is the warm-up: a vendor that prepares something per point set (PLCnext
    registers a group for each) does it once, not every minute.
    """
    read: set[Point] = set()
    ticks = int(MINUTE / schedule.tick)
    counts = [0, 0]
    for tick in range(2 * ticks):
        if tick == ticks:
            before = await simulator.requests()
        at = tick * schedule.tick
        due, classes = schedule.due(points, at, read, ())
        await client.read(due)
        schedule.done(at, classes)
        read.update(due)
        counts[tick >= ticks] += len(due)
    return await simulator.requests() - before, ticks, counts[1]


async def bench_vendor(vendor: str, size: int) -> dict[str, Any]:
    """Return one vendor's row: requests a minute with the mix, and with every point fast."""
    cls = client_class(vendor)
    points = [cls.validate_point(point) for point in VENDORS[vendor].points(size)]
    normal = cls.default_scan_interval
    intervals = {FAST: DEFAULT_FAST_INTERVAL, NORMAL: normal, SLOW: DEFAULT_SLOW_INTERVAL}
    simulator = Simulator(vendor, size)
    if not await simulator.start():
        return {}
    client = make_client(vendor, simulator.info, poll_interval=normal)
    try:
        await client.connect()
        await client.read(points)  # warm-up: sessions, plans, names
        classes = PollSchedule()
        classes.configure(mixed(points), intervals)
        mix, polls, mix_points = await a_minute(client, simulator, points, classes)
        every = PollSchedule()
        every.configure(dict.fromkeys(points, FAST), intervals)
        fast, _, fast_points = await a_minute(client, simulator, points, every)
    finally:
        await client.close()
        await simulator.stop()
    return {
        "check": "poll_classes",
        "vendor": vendor,
        "points": size,
        "intervals_s": [intervals[name] for name in (FAST, NORMAL, SLOW)],
        "polls_per_minute": polls,
        "requests_per_minute": mix,
        "all_fast_requests_per_minute": fast,
        "points_read_per_minute": mix_points,
        "all_fast_points_read_per_minute": fast_points,
    }


async def poll_class_rows(vendors: list[str], sizes: list[int]) -> list[dict[str, Any]]:
    """Return a row per vendor and size (none for a vendor whose simulator did not start)."""
    rows = [await bench_vendor(vendor, size) for vendor in vendors for size in sizes]
    return [row for row in rows if row]


def poll_class_text(row: dict[str, Any]) -> str:
    """Return one row as a line of the benchmark's text."""
    fast, normal, slow = (f"{seconds:g} s" for seconds in row["intervals_s"])
    share = row["requests_per_minute"] / max(1, row["all_fast_requests_per_minute"])
    return (
        f"poll classes ({row['vendor']}, {row['points']} points: 10 % fast every {fast},"
        f" 60 % normal every {normal}, 30 % slow every {slow}; a virtual minute of"
        f" {row['polls_per_minute']} polls): {row['requests_per_minute']} requests/min"
        f" ({row['points_read_per_minute']} point reads); every point fast:"
        f" {row['all_fast_requests_per_minute']} requests/min"
        f" ({row['all_fast_points_read_per_minute']} point reads); requests {share:.0%} of it"
    )


def main() -> int:
    """Run the poll classes' lines alone and print them."""
    parser = argparse.ArgumentParser(prog="python -m bench.poll_classes", description=__doc__)
    parser.add_argument("--json", action="store_true", help="one JSON object per line")
    parser.add_argument("--points", type=int, nargs="+", default=[100])
    args = parser.parse_args()
    rows = asyncio.run(poll_class_rows(ready_vendors(), args.points))
    for row in rows:
        print(json.dumps(row) if args.json else poll_class_text(row))
    return 0 if rows else 1


if __name__ == "__main__":
    sys.exit(main())
