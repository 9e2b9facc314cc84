"""Poll benchmark: requests, time and client CPU per poll, for every vendor with a simulator.

Run it as `scripts/bench [--json]`. Each simulator runs in a subprocess (`python -m bench.serve`,
driven over stdin), so the CPU figure is the client's own: planning, encoding, TLS, decoding.
Pacing is off (the client class's `request_interval` is set to 0), so poll_ms is the protocol's
cost, not the vendor's advised request rate. Requests are counted at the simulator.
"""

from __future__ import annotations

import argparse
import asyncio
from collections.abc import Callable
import json
from pathlib import Path
import platform
import shlex
import statistics
import sys
import tempfile
import time
from typing import IO, Any

import aiohttp
from snap7.async_client import AsyncISOTCPConnection

from custom_components.plc_bridge.plc import ConnectionConfig, PlcClient, Point, TlsMode
from custom_components.plc_bridge.plc.http import HttpTransport
from custom_components.plc_bridge.plc.vendors import VENDORS as ALL_VENDORS, client_class

from .ha_checks import check_text, ha_checks
from .points import VENDORS

ROOT = Path(__file__).resolve().parent.parent
CPU_TARGET_MS = 10.0  # per 1,000-point poll


class Simulator:
    """A simulator in a subprocess, driven over its --control pipe."""

    def __init__(self, vendor: str, points: int = 1000) -> None:
        """Remember the vendor and how many points it must hold; `start` launches it."""
        self.vendor = vendor
        self.points = points
        self.info: dict[str, Any] = {}
        self._process: asyncio.subprocess.Process | None = None
        self._log: IO[bytes] | None = None  # the simulator's own logging, shown if it fails

    async def start(self) -> bool:
        """Launch the simulator on a free loopback port; False when it has none."""
        self._log = tempfile.TemporaryFile()  # noqa: SIM115 - closed in stop()
        self._process = await asyncio.create_subprocess_exec(
            *(sys.executable, "-m", "bench.serve", self.vendor, str(self.points)),
            cwd=ROOT,
            stdin=asyncio.subprocess.PIPE,
            stdout=asyncio.subprocess.PIPE,
            stderr=self._log,
        )
        line = await self._line()
        if not line:
            await self._process.wait()
            self._log.seek(0)
            why = self._log.read().decode(errors="replace").strip()
            print(f"{self.vendor}: skipped, its simulator did not start: {why}", file=sys.stderr)
            return False
        self.info = json.loads(line)
        return True

    async def _line(self) -> bytes:
        """Read one line of the simulator's output (empty at its end)."""
        assert self._process is not None
        assert self._process.stdout is not None
        return await asyncio.wait_for(self._process.stdout.readline(), timeout=30)

    async def requests(self) -> int:
        """Return how many requests the simulator has answered so far."""
        return await self._count("requests")

    async def connections(self) -> int:
        """Return how many client connections (TLS handshakes on HTTPS) it has accepted."""
        return await self._count("connections")

    async def _count(self, what: str) -> int:
        """Ask the simulator for one of its counters."""
        assert self._process is not None
        assert self._process.stdin is not None
        self._process.stdin.write(f"{what}\n".encode())
        await self._process.stdin.drain()
        return int(json.loads(await self._line())[self.vendor])

    async def stop(self) -> None:
        """Close its input, which stops it, and wait for it."""
        if self._process is not None and self._process.stdin is not None:
            self._process.stdin.close()
            await self._process.wait()
        if self._log is not None:
            self._log.close()


def make_client(
    vendor: str,
    info: dict[str, Any],
    session: aiohttp.ClientSession | None = None,
    poll_interval: float = 5.0,
) -> PlcClient:
    """Return an unpaced client for the simulator, pinned to its certificate if it has one.

    Without `session`, the client makes its own, which keeps a connection for `poll_interval`.
    """
    cls = client_class(vendor)
    cls.request_interval = 0.0
    tls = TlsMode.PIN if info.get("fingerprint") else TlsMode.NONE
    config = ConnectionConfig(
        host=info["host"],
        port=int(info["port"]),
        username=info.get("username") or "",
        password=info.get("password") or "",
        tls=tls if tls in cls.tls_modes else cls.default_tls,
        fingerprint=info.get("fingerprint") or "",
        poll_interval=poll_interval,
    )
    return cls(config, session)


TRANSPORT_CPU = [0.0]
"""Client CPU seconds spent inside the transport (aiohttp with TLS, or the ISO-on-TCP socket)."""


def _timed[**P, R](method: Callable[P, Any]) -> Callable[P, Any]:
    """Wrap an async transport method so its CPU time is added to TRANSPORT_CPU."""

    async def wrapper(*args: P.args, **kwargs: P.kwargs) -> Any:
        started = time.process_time()
        try:
            return await method(*args, **kwargs)
        finally:
            TRANSPORT_CPU[0] += time.process_time() - started

    return wrapper


def time_transports() -> None:
    """Separate the transport's CPU from the protocol's (planning, encoding, decoding)."""
    HttpTransport.request = _timed(HttpTransport.request)  # type: ignore[method-assign]
    AsyncISOTCPConnection.send_data = _timed(AsyncISOTCPConnection.send_data)  # type: ignore[method-assign]
    AsyncISOTCPConnection.receive_data = _timed(AsyncISOTCPConnection.receive_data)  # type: ignore[method-assign]


async def measure(
    client: PlcClient, simulator: Simulator, points: list[Point], polls: int
) -> dict[str, Any]:
    """Poll `polls` times after a warm-up poll; return the medians and the request count."""
    await client.read(points)  # warm-up: TLS session, connection pool, token
    walls: list[float] = []
    cpus: list[float] = []
    protocol: list[float] = []
    requests: list[int] = []
    failed = 0
    for _ in range(polls):
        before = await simulator.requests()
        TRANSPORT_CPU[0] = 0.0
        wall, cpu = time.perf_counter(), time.process_time()
        result = await client.read(points)
        cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
        protocol.append((cpu - TRANSPORT_CPU[0]) * 1000)
        requests.append(await simulator.requests() - before)
        walls.append(wall * 1000)
        cpus.append(cpu * 1000)
        failed = sum(1 for point in points if not result.values[point].ok)
    return {
        "requests_per_poll": max(requests),
        "poll_ms": round(statistics.median(walls), 2),
        "cpu_ms_per_poll": round(statistics.median(cpus), 2),
        "protocol_cpu_ms_per_poll": round(statistics.median(protocol), 2),
        "failed_points": failed,
    }


async def bench_vendor(vendor: str, sizes: list[int], polls: int) -> list[dict[str, Any]]:
    """Benchmark one vendor at every size; empty when it has no simulator or usable points."""
    spec = VENDORS[vendor]
    cls = client_class(vendor)
    try:
        samples = {size: [cls.validate_point(p) for p in spec.points(size)] for size in sizes}
    except Exception as err:  # a guessed address syntax: say so and go on
        print(f"{vendor}: skipped, its benchmark points do not validate: {err}", file=sys.stderr)
        return []
    simulator = Simulator(vendor, max(sizes))
    if not await simulator.start():
        return []
    client = make_client(vendor, simulator.info)
    rows = []
    try:
        await client.connect()
        for size, points in samples.items():
            row = {"vendor": vendor, "points": size, "naive_requests": size}
            row |= await measure(client, simulator, points, polls)
            row["cpu_ms_per_1000_points"] = round(row["cpu_ms_per_poll"] * 1000 / size, 2)
            row["target_requests"] = spec.target(size) if spec.target else None
            if spec.items is not None:
                row["data_items"] = spec.items(points)
            rows.append(row)
    finally:
        await client.close()
        await simulator.stop()
    return rows


def table(rows: list[dict[str, Any]], command: str) -> str:
    """Return the rows as a text table, with the command and the targets."""
    head = ("vendor", "points", "requests/poll", "target", "naive", "poll ms", "CPU ms/poll")
    head += ("protocol CPU ms", "CPU ms/1k pts")
    lines = [f"$ {command}", f"# Python {platform.python_version()}, {platform.machine()}", ""]
    lines.append(f"{head[0]:<9}{head[1]:>7}{head[2]:>15}{head[3]:>8}{head[4]:>7}")
    lines[-1] += f"{head[5]:>9}{head[6]:>13}{head[7]:>17}{head[8]:>15}"
    for row in rows:
        target = "-" if row["target_requests"] is None else str(row["target_requests"])
        line = f"{row['vendor']:<9}{row['points']:>7}{row['requests_per_poll']:>15}{target:>8}"
        line += f"{row['naive_requests']:>7}{row['poll_ms']:>9.2f}{row['cpu_ms_per_poll']:>13.2f}"
        line += f"{row['protocol_cpu_ms_per_poll']:>17.2f}"
        line += f"{row['cpu_ms_per_1000_points']:>15.2f}"
        if row.get("data_items") is not None:
            line += f"   ({row['data_items']} <data> items for {row['points']} points)"
        if row["failed_points"]:
            line += f"   ({row['failed_points']} points failed)"
        lines.append(line)
    lines.append("")
    targets = ", ".join(f"{v}: {spec.target_text}" for v, spec in VENDORS.items())
    lines.append(
        f"targets: requests/poll {targets}; protocol CPU per 1,000-point poll < {CPU_TARGET_MS} ms"
    )
    lines.append(
        "protocol CPU = client CPU minus the transport (aiohttp + TLS, or the ISO-on-TCP socket)"
    )
    lines.append("pacing off (request_interval = 0); simulators in subprocesses on 127.0.0.1")
    return "\n".join(lines)


def ready_vendors() -> list[str]:
    """Return the implemented vendors with a benchmark entry; a half-written one is skipped."""
    ready = []
    for vendor in (v for v in ALL_VENDORS if v in VENDORS):
        try:
            client_class(vendor)
        except KeyError:
            continue
        except Exception as err:  # another engineer's module mid-way: report it, bench the rest
            print(f"{vendor}: skipped, its client does not load: {err!r}", file=sys.stderr)
            continue
        ready.append(vendor)
    return ready


async def run(sizes: list[int], polls: int) -> list[dict[str, Any]]:
    """Benchmark every implemented vendor that has a benchmark entry."""
    rows: list[dict[str, Any]] = []
    for vendor in ready_vendors():
        rows += await bench_vendor(vendor, sizes, polls)
    return rows


def main() -> int:
    """Parse the command line, run, print."""
    parser = argparse.ArgumentParser(prog="scripts/bench", description=__doc__)
    parser.add_argument("--json", action="store_true", help="one JSON object per line")
    parser.add_argument("--points", type=int, nargs="+", default=[10, 100, 1000])
    parser.add_argument("--polls", type=int, default=5, help="timed polls per size (median)")
    parser.add_argument(
        "--ha",
        action=argparse.BooleanOptionalAction,
        help="also run the Home Assistant checks: quiet poll, setup, machine kinds (default: on)",
    )
    args = parser.parse_args()
    time_transports()
    rows = asyncio.run(run(args.points, args.polls))
    # Imported here: bench.keepalive and bench.poll_classes build on this module's driver.
    from .keepalive import keepalive_rows, keepalive_text  # noqa: PLC0415
    from .poll_classes import poll_class_rows, poll_class_text  # noqa: PLC0415

    keepalive = asyncio.run(keepalive_rows(ready_vendors()))
    classes = asyncio.run(poll_class_rows(ready_vendors(), [100]))
    checks = ha_checks() if args.ha is not False else None
    if isinstance(checks, str):
        print(f"Home Assistant checks could not run:\n{checks}")
    if args.json:
        keys = ("vendor", "points", "requests_per_poll", "naive_requests", "poll_ms")
        for row in rows:
            extra = ("cpu_ms_per_poll", "cpu_ms_per_1000_points", "protocol_cpu_ms_per_poll")
            extra += ("data_items",)
            print(json.dumps({key: row[key] for key in (*keys, *extra) if key in row}))
        for result in [*keepalive, *classes, *(checks if isinstance(checks, list) else [])]:
            print(json.dumps(result))
    else:
        print(table(rows, shlex.join(["scripts/bench", *sys.argv[1:]])))
        for result in keepalive:
            print(keepalive_text(result))
        for result in classes:
            print(poll_class_text(result))
        for result in checks if isinstance(checks, list) else []:
            print(check_text(result))
    checks_ok = checks is None or (isinstance(checks, list) and all(c["passed"] for c in checks))
    return 0 if rows and checks_ok else 1


if __name__ == "__main__":
    sys.exit(main())
