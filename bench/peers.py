"""PLCnext against a peer: client CPU of one group read, ours and pyPLCn's, on the same variables.

Run it as `python -m bench.peers`. The simulator runs in a subprocess (this module with
`--serve N`, publishing `Bench.Value0` .. `Bench.Value<N-1>`), so each CPU figure is the client's
own: TLS, HTTP, JSON and, for ours, placing and decoding every value. pyPLCn (an independent
PLCnext REST client) polls a group from a thread of its own; here its poll body (`_task`) runs
once per poll in this thread, so its CPU is measured the same way as ours.
"""

from __future__ import annotations

import argparse
import asyncio
from collections.abc import Callable
import json
import logging
from pathlib import Path
import platform
import shlex
import statistics
import subprocess
import sys
import time
from typing import IO, Any

from .points import plcnext_points
from .poll import make_client

ROOT = Path(__file__).resolve().parent.parent
PREFIX = "Arp.Plc.Eclr/"  # the component pyPLCn registers its names relative to
PYPLCN_PORT = 443  # pyPLCn's fixed port: its requests are sent to the simulator's port instead


class Simulator:
    """The PLCnext simulator in a subprocess with `size` bench variables, driven over stdin."""

    def __init__(self, size: int) -> None:
        """Start it and read what it says about itself (host, port, user, certificate)."""
        self._process = subprocess.Popen(
            [sys.executable, "-m", "bench.peers", "--serve", str(size)],
            cwd=ROOT,
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
        )
        self.info: dict[str, Any] = json.loads(self._line())

    def _line(self) -> str:
        """Read one line of its output; fail when it has ended."""
        assert self._process.stdout is not None
        line = self._process.stdout.readline()
        if not line:
            raise RuntimeError("the PLCnext simulator did not start")
        return line

    def requests(self) -> int:
        """Return how many requests it has answered so far."""
        stdin: IO[str] | None = self._process.stdin
        assert stdin is not None
        stdin.write("requests\n")
        stdin.flush()
        return int(json.loads(self._line())["plcnext"])

    def stop(self) -> None:
        """Close its input, which stops it, and wait for it."""
        if self._process.stdin is not None:
            self._process.stdin.close()
        self._process.wait(timeout=30)


def timed(poll: Callable[[], Any], simulator: Simulator, polls: int) -> dict[str, float]:
    """Run a warm-up poll and `polls` timed ones; return medians and requests per poll."""
    poll()
    cpus: list[float] = []
    walls: list[float] = []
    requests: list[int] = []
    for _ in range(polls):
        before = simulator.requests()
        wall, cpu = time.perf_counter(), time.process_time()
        poll()
        cpus.append((time.process_time() - cpu) * 1000)
        walls.append((time.perf_counter() - wall) * 1000)
        requests.append(simulator.requests() - before)
    return {
        "cpu_ms": statistics.median(cpus),
        "wall_ms": statistics.median(walls),
        "requests": max(requests),
    }


def ours(simulator: Simulator, size: int, polls: int) -> dict[str, float]:
    """Poll `size` variables with PLC Bridge's client; every value placed and decoded."""
    points = plcnext_points(size)
    loop = asyncio.new_event_loop()
    client = make_client("plcnext", simulator.info)
    try:
        loop.run_until_complete(client.connect())
        failed: list[int] = []

        def poll() -> None:
            """One poll of every point."""
            result = loop.run_until_complete(client.read(points))
            failed.append(sum(1 for point in points if not result.values[point].ok))

        row = timed(poll, simulator, polls)
        row["failed"] = max(failed)
    finally:
        loop.run_until_complete(client.close())
        loop.close()
    return row


def peer_class() -> Any:
    """Import pyPLCn without its import-time logging.basicConfig (it logs its access token)."""
    root = logging.getLogger()
    handlers, level = list(root.handlers), root.level
    try:
        from pyPLCn import pyPLCn  # noqa: PLC0415 - only this benchmark needs it
    finally:
        root.handlers[:] = handlers
        root.setLevel(level)
    return pyPLCn


def redirected(port: int) -> Any:
    """Return a requests adapter that sends pyPLCn's requests for port 443 to `port`."""
    from requests.adapters import HTTPAdapter  # noqa: PLC0415 - pyPLCn's own dependency

    class ToPort(HTTPAdapter):
        """Rewrite the port of each request, then send it."""

        def send(self, request: Any, *args: Any, **kwargs: Any) -> Any:
            """Send the request to the simulator's port."""
            request.url = request.url.replace(f":{PYPLCN_PORT}/", f":{port}/", 1)
            return super().send(request, *args, **kwargs)

    return ToPort()


def peer(simulator: Simulator, size: int, polls: int) -> dict[str, float]:
    """Poll the same variables with pyPLCn: its group, its poll body once a poll."""
    return pyplcn(simulator, size, polls, by_name=False)


def peer_by_name(simulator: Simulator, size: int, polls: int) -> dict[str, float]:
    """As `peer`, then every value asked by name (`get_var`: a search of the list each)."""
    return pyplcn(simulator, size, min(polls, LOOKUP_POLLS), by_name=True)


def pyplcn(simulator: Simulator, size: int, polls: int, *, by_name: bool) -> dict[str, float]:
    """Poll with pyPLCn; `by_name`: then ask it for every variable's value, as a user would."""
    info = simulator.info
    client = peer_class()()
    client._run_flag = True
    client._poll_time = 0
    if int(info["port"]) != PYPLCN_PORT:
        client.s.mount(f"https://{info['host']}:{PYPLCN_PORT}/", redirected(int(info["port"])))
    names = [point.address.removeprefix(PREFIX) for point in plcnext_points(size)]
    client.set_var_names(names)
    STATIONS.append(len(STATIONS) + 100)  # a station has one session: a new one for each
    client.connect(info["host"], info["username"] or "", info["password"] or "", 0, STATIONS[-1])
    get = client.s.get

    def read_once(*args: Any, **kwargs: Any) -> Any:
        """Send pyPLCn's group read, then end its poll loop after this one round."""
        client._run_flag = False
        return get(*args, **kwargs)

    client.s.get = read_once

    def poll() -> None:
        """One round of pyPLCn's poll loop: GET the group, json.loads, keep the list."""
        client._run_flag = True
        client._task()
        if by_name:
            for name in names:
                client.get_var(name)

    try:
        row = timed(poll, simulator, polls)
        got = client.read_vars
        row["failed"] = size - sum(1 for entry in got if entry.get("value") is not None)
        if not client.is_connected():
            raise RuntimeError(f"pyPLCn is not connected: {client.last_error}")
    finally:
        unregister(client, info["host"])
        client.close()
    return row


def unregister(client: Any, host: str) -> None:
    """Delete pyPLCn's group (it has no call for it): the next one would be an identical group,
    which the PLC reuses with a 200 that pyPLCn takes for a refusal (it expects 201).
    """
    session = client._session_id
    client.s.delete(
        f"https://{host}:{PYPLCN_PORT}/_pxc_api/v1.2/groups/{client.vars_group}?sessionID={session}",
        headers={"Authorization": f"Bearer {client._access_token}"},
        verify=False,
        timeout=10,
    )


STATIONS: list[int] = []  # pyPLCn's station ids so far
LOOKUP_POLLS = 3  # get_var searches the list: 10,000 lookups take seconds
CLIENTS: tuple[tuple[str, Callable[[Simulator, int, int], dict[str, float]]], ...] = (
    ("plc_bridge", ours),
    ("pyPLCn", peer),
    ("pyPLCn+get", peer_by_name),
)


def table(rows: list[dict[str, Any]], command: str) -> str:
    """Return the rows as text, with the command and what each client does per poll."""
    lines = [f"$ {command}", f"# Python {platform.python_version()}, {platform.machine()}", ""]
    head = ("variables", "client", "requests", "poll ms", "CPU ms/poll", "CPU ms/1,000")
    lines.append(f"{head[0]:>9}  {head[1]:<12}{head[2]:>9}{head[3]:>9}{head[4]:>13}{head[5]:>14}")
    for row in rows:
        line = f"{row['size']:>9}  {row['client']:<12}{row['requests']:>9}"
        per_1000 = row["cpu_ms"] * 1000 / row["size"]
        line += f"{row['wall_ms']:>9.2f}{row['cpu_ms']:>13.2f}{per_1000:>14.2f}"
        if row["failed"]:
            line += f"   ({row['failed']} values missing)"
        lines.append(line)
    lines += [
        "",
        "plc_bridge: one group read (registered with a pathPrefix), every value matched to its",
        "  point, decoded for its IEC type and wrapped in a PointResult",
        "pyPLCn 1.0.3: one group read (requests, verify=False), json.loads, the list kept as sent:",
        "  no value checked, matched to its name or decoded",
        f"pyPLCn+get: the same, then get_var of every variable (a search of the list each;"
        f" {LOOKUP_POLLS} polls)",
        "both over TLS to the simulator in a subprocess on 127.0.0.1; medians of the timed polls",
    ]
    return "\n".join(lines)


def serve(size: int) -> int:
    """Run the PLCnext simulator with `size` bench variables until standard input closes."""
    from simulators.__main__ import run  # noqa: PLC0415 - only the simulator's process needs it

    options = {"plcnext": {"bench": size}}
    return asyncio.run(run(["plcnext"], 0, as_json=True, control=True, options=options))


def main() -> int:
    """Parse the command line, run both clients at every size, print."""
    parser = argparse.ArgumentParser(prog="python -m bench.peers", description=__doc__)
    parser.add_argument("--points", type=int, nargs="+", default=[1000, 5000, 10000])
    parser.add_argument("--polls", type=int, default=20, help="timed polls per size (median)")
    parser.add_argument("--json", action="store_true", help="one JSON object per line")
    parser.add_argument("--serve", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.serve is not None:
        return serve(args.serve)
    simulator = Simulator(max(args.points))
    rows: list[dict[str, Any]] = []
    try:
        for size in args.points:
            for name, run in CLIENTS:
                rows.append({"size": size, "client": name} | run(simulator, size, args.polls))
    finally:
        simulator.stop()
    if args.json:
        for row in rows:
            print(json.dumps(row | {"cpu_ms_per_1000": row["cpu_ms"] * 1000 / row["size"]}))
    else:
        print(table(rows, shlex.join(["python", "-m", "bench.peers", *sys.argv[1:]])))
    return 0 if all(not row["failed"] for row in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
