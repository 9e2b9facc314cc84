"""The plant's PLCs for bench/test_plant.py: `python -m bench.plant_sims COUNT CHANGING PERIOD [F]`.

COUNT S7-200 SMART simulators in this one process (not Home Assistant's), one JSON line each
telling where it listens; every PERIOD seconds the first CHANGING words (VW0, VW2, ...) of each
take new values, as a running process would. With F (seconds), every F seconds the next PLC
goes away for F / 2 seconds (a reboot). Runs until standard input closes.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import sys
import threading

from simulators.s7_smart import DEFAULT_PASSWORD, DEFAULT_USER, S7SmartSimulator


def _wait_for_eof(loop: asyncio.AbstractEventLoop, stop: asyncio.Event) -> None:
    """Set `stop` once standard input closes (run in a daemon thread)."""
    for _line in sys.stdin:
        pass
    loop.call_soon_threadsafe(stop.set)


async def faults(simulators: list[S7SmartSimulator], every: float, stop: asyncio.Event) -> None:
    """Take the PLCs away in turn, each for half of `every` seconds, on the same port."""
    index = 0
    while not stop.is_set():
        with contextlib.suppress(TimeoutError):
            await asyncio.wait_for(stop.wait(), every / 2)
        simulator = simulators[index % len(simulators)]
        await simulator.stop()
        with contextlib.suppress(TimeoutError):
            await asyncio.wait_for(stop.wait(), every / 2)
        await simulator.start(simulator.host, simulator.port)
        index += 1


async def serve(count: int, changing: int, period: float, fault: float = 0.0) -> None:
    """Start the simulators, print where they are, change their values until stdin closes."""
    simulators = []
    for _ in range(count):
        simulator = S7SmartSimulator()
        await simulator.start()
        simulators.append(simulator)
        info = {
            "host": simulator.host,
            "port": simulator.port,
            "fingerprint": simulator.fingerprint,
            "username": DEFAULT_USER,
            "password": DEFAULT_PASSWORD,
        }
        print(json.dumps(info), flush=True)
    stop = asyncio.Event()
    loop = asyncio.get_running_loop()
    threading.Thread(target=_wait_for_eof, args=(loop, stop), daemon=True).start()
    breaking = asyncio.create_task(faults(simulators, fault, stop)) if fault else None
    tick = 0
    while not stop.is_set():
        tick += 1
        for simulator in simulators:
            for index in range(changing):
                simulator.set(f"VW{2 * index}", (tick * 7 + index) % 30000)
        with contextlib.suppress(TimeoutError):
            await asyncio.wait_for(stop.wait(), period)
    if breaking is not None:
        await breaking
    for simulator in simulators:
        await simulator.stop()


def main() -> int:
    """Parse the three arguments and serve."""
    count, changing, period = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3])
    fault = float(sys.argv[4]) if len(sys.argv) > 4 else 0.0
    asyncio.run(serve(count, changing, period, fault))
    return 0


if __name__ == "__main__":
    sys.exit(main())
