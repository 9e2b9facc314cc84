"""Which S7 library to build on: round trips and wall time of one 100-point poll, per library.

Run it as `.venv/bin/python -m bench.s7_libraries`. Our S7 simulator (python-snap7's server
with the extensions in simulators/) runs in this process on 127.0.0.1 and counts the requests it
answers; every library reads the same 100 scattered points (REAL, INT and BOOL over DB1..DB3 and
M) from it, then the same points plus one in a DB the CPU does not have (DB99), to see whether a
bad address hides the other values. pyS7 is a bench dependency (requirements_test.txt).
"""

from __future__ import annotations

import asyncio
from collections.abc import Awaitable, Callable, Sequence
from dataclasses import dataclass
import logging
import statistics
import sys
import time
from typing import Any

from snap7.async_client import AsyncClient
from snap7.client import Client
from snap7.type import Area

from custom_components.plc_bridge.plc import ConnectionConfig, Point
from custom_components.plc_bridge.plc.vendors.s7 import S7Client
from simulators.s7 import S7Simulator

POLLS = 20  # timed polls per library (median)
CHUNK = 20  # python-snap7's MAX_VARS: read_multi_vars refuses more items
SIZES = {"REAL": 4, "INT": 2, "BOOL": 1}


@dataclass(frozen=True, slots=True)
class Item:
    """One point of the poll, in the terms every library takes."""

    area: str  # "DB" or "M"
    db: int
    start: int
    data_type: str  # REAL, INT or BOOL
    bit: int = 0

    @property
    def address(self) -> str:
        """The STEP 7 address (our client's form)."""
        width = {"REAL": "D", "INT": "W", "BOOL": "X"}[self.data_type]
        if self.area == "M":
            return f"M{self.start}.{self.bit}" if width == "X" else f"M{width}{self.start}"
        bit = f".{self.bit}" if width == "X" else ""
        return f"DB{self.db}.DB{width}{self.start}{bit}"


def poll_items() -> list[Item]:
    """100 points, 25 in each of DB1, DB2, DB3 and M, 8 bytes apart, REAL/INT/BOOL in turn."""
    items = []
    for index in range(100):
        area, db = ("DB", 1 + index % 4) if index % 4 < 3 else ("M", 0)
        data_type = ("REAL", "INT", "BOOL")[index % 3]
        items.append(Item(area, db, index // 4 * 8, data_type, index % 8))
    return items


BAD = Item("DB", 99, 0, "INT")


def snap7_item(item: Item) -> dict[str, Any]:
    """python-snap7's read_multi_vars item (bytes of an area)."""
    area = Area.DB if item.area == "DB" else Area.MK
    return {"area": area, "db_number": item.db, "start": item.start, "size": SIZES[item.data_type]}


def chunks[T](items: Sequence[T], size: int) -> list[Sequence[T]]:
    """Split into calls of `size` items (python-snap7 refuses more than 20)."""
    return [items[start : start + size] for start in range(0, len(items), size)]


type Poll = Callable[[list[Item], int], Awaitable[str]]
"""Read the items (python-snap7: `size` items a call) and say what came back."""


@dataclass(frozen=True, slots=True)
class Contender:
    """A connected library: its poll, how to close it, and whether it runs on the event loop."""

    poll: Poll
    close: Callable[[], Awaitable[Any]]
    asyncio: str


async def snap7_async(sim: S7Simulator) -> Contender:
    """python-snap7 3.3.0 AsyncClient.read_multi_vars."""
    client = AsyncClient()
    await client.connect(sim.host, 0, 1, sim.port)

    async def poll(items: list[Item], size: int) -> str:
        values = 0
        for part in chunks([snap7_item(item) for item in items], size):
            values += len((await client.read_multi_vars(list(part)))[1])
        return f"{values} values"

    return Contender(poll, client.disconnect, "yes")


async def snap7_sync(sim: S7Simulator) -> Contender:
    """python-snap7 3.3.0 Client.read_multi_vars (its optimizer), in a worker thread."""
    client = Client()
    await asyncio.to_thread(client.connect, sim.host, 0, 1, sim.port)

    def read(items: list[Item], size: int) -> str:
        values = 0
        for part in chunks([snap7_item(item) for item in items], size):
            values += len(client.read_multi_vars(list(part))[1])
        return f"{values} values"

    async def poll(items: list[Item], size: int) -> str:
        return await asyncio.to_thread(read, items, size)

    return Contender(poll, lambda: asyncio.to_thread(client.disconnect), "executor")


async def pys7(sim: S7Simulator) -> Contender:
    """pyS7 3.1.2 AsyncS7Client.read_detailed (its optimizer, results per tag)."""
    from pyS7 import AsyncS7Client, DataType, MemoryArea, S7Tag  # noqa: PLC0415 - optional

    kinds = {"REAL": DataType.REAL, "INT": DataType.INT, "BOOL": DataType.BIT}

    def tag(item: Item) -> S7Tag:
        area = MemoryArea.DB if item.area == "DB" else MemoryArea.MERKER
        bit = item.bit if item.data_type == "BOOL" else 0
        db = item.db if item.area == "DB" else 0
        return S7Tag(area, db, kinds[item.data_type], item.start, bit, 1)

    client = AsyncS7Client(sim.host, 0, 1, port=sim.port)
    await client.connect()

    async def poll(items: list[Item], size: int) -> str:
        results = await client.read_detailed([tag(item) for item in items])
        failed = [result for result in results if not result.success]
        return f"{len(results) - len(failed)} values, {len(failed)} errors"

    return Contender(poll, client.disconnect, "yes")


async def ours(sim: S7Simulator) -> Contender:
    """PLC Bridge's S7Client.read (PDU-packed multi-variable reads, a result per point)."""
    client = S7Client(ConnectionConfig(host=sim.host, port=sim.port))
    await client.connect()

    async def poll(items: list[Item], size: int) -> str:
        points = [Point(item.address, item.data_type) for item in items]
        results = (await client.read(points)).values.values()
        failed = sum(1 for result in results if not result.ok)
        return f"{len(results) - failed} values, {failed} errors"

    return Contender(poll, client.close, "yes")


CONTENDERS: dict[str, Callable[[S7Simulator], Awaitable[Contender]]] = {
    "python-snap7 AsyncClient.read_multi_vars": snap7_async,
    "python-snap7 Client.read_multi_vars": snap7_sync,
    "pyS7 AsyncS7Client.read_detailed": pys7,
    "PLC Bridge S7Client.read": ours,
}


async def attempt(poll: Awaitable[str]) -> str:
    """Return what a poll gave, or what it raised (the finding, for a library)."""
    try:
        return await poll
    except Exception as err:  # what the library raises is the finding
        return f"raises {type(err).__name__}"


async def measure(name: str, sim: S7Simulator, items: list[Item]) -> tuple[str, ...]:
    """Return one table row: round trips, wall time, and what one bad DB does."""
    try:
        contender = await CONTENDERS[name](sim)
    except ImportError as err:
        return name, "-", "-", "-", f"not installed ({err.name})", ""
    poll = contender.poll
    try:
        whole = await attempt(poll(items, len(items)))
        await poll(items, CHUNK)  # warm-up
        before = sim.requests
        await poll(items, CHUNK)
        trips = sim.requests - before
        if name.startswith("PLC Bridge"):
            trips -= 1  # its CPU state request (SZL 0x0424), which the others do not make
        walls = []
        for _ in range(POLLS):
            started = time.perf_counter()
            await poll(items, CHUNK)
            walls.append((time.perf_counter() - started) * 1000)
        bad = await attempt(poll([*items, BAD], CHUNK))
    finally:
        await contender.close()
    wall = f"{statistics.median(walls):.2f}"
    return name, contender.asyncio, str(trips), wall, whole, bad


async def run() -> list[tuple[str, ...]]:
    """Start the simulator, measure every contender in turn, stop it."""
    sim = S7Simulator(dbs={1: 256, 2: 256, 3: 256}, pdu_size=480)
    await sim.start()
    try:
        return [await measure(name, sim, poll_items()) for name in CONTENDERS]
    finally:
        await sim.stop()


def main() -> int:
    """Print the table."""
    logging.getLogger("snap7").setLevel(logging.CRITICAL)  # its server logs every missing DB
    rows = asyncio.run(run())
    print("$ .venv/bin/python -m bench.s7_libraries")
    print(f"# Python {sys.version.split()[0]}; simulator PDU 480, 20 items a request; 100 points")
    head = ("library", "asyncio", "trips", "wall ms", "100 in one call", "+ DB99.DBW0 (missing)")
    widths = (42, 10, 7, 9, 22, 0)
    for row in (head, *rows):
        print("".join(f"{text:<{width}}" for text, width in zip(row, widths, strict=True)))
    print("trips: requests the simulator answered for one poll (ours without its CPU state);")
    print(f"python-snap7 is called with {CHUNK} items at a time; wall ms: median of {POLLS} polls")
    return 0


if __name__ == "__main__":
    sys.exit(main())
