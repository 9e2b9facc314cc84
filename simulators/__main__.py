"""Start every simulator that exists on loopback: `python -m simulators [--only VENDOR ...]`.

Prints where each one listens, its credentials and, for TLS ones, the certificate fingerprint
to pin. Runs until Ctrl-C (or SIGTERM). With `--demo`, a simulator that has `animate(elapsed)`
is called about once a second, so that some of its values move as a running process would.
With `--control`, it runs until standard input closes and answers each line "requests" with one
JSON line of request counters per vendor: the benchmarks drive a simulator in a subprocess this
way, so their CPU figures are the client's own.
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
from dataclasses import dataclass
import importlib
import inspect
import json
from pathlib import Path
import signal
import sys
import threading
import time
from typing import Any

from .base import make_certificate


@dataclass(frozen=True, slots=True)
class Entry:
    """Where a vendor's simulator lives and the port the demo gives it."""

    vendor: str
    module: str
    class_name: str
    port: int


SIMULATORS = (
    Entry("s7_smart", "simulators.s7_smart", "S7SmartSimulator", 8443),
    Entry("tecomat", "simulators.tecomat", "TecomatSimulator", 8080),
    Entry("plcnext", "simulators.plcnext", "PlcnextSimulator", 5050),
    Entry("softplc", "simulators.softplc", "SoftplcSimulator", 8081),
    Entry("s7", "simulators.s7", "S7Simulator", 10102),
    Entry("logo", "simulators.logo", "LogoSimulator", 10103),
)


def load(entry: Entry) -> tuple[Any, type[Any]] | None:
    """Return (module, simulator class) of a vendor, or None while its module does not exist."""
    try:
        module = importlib.import_module(entry.module)
    except ModuleNotFoundError as err:
        if err.name is not None and entry.module.startswith(err.name):
            return None
        raise
    cls = getattr(module, entry.class_name, None)
    if cls is None:  # tolerate another class name: the one class whose name ends in Simulator
        found = [
            value
            for name, value in vars(module).items()
            if inspect.isclass(value) and name.endswith("Simulator") and name != "HttpSimulator"
        ]
        if len(found) != 1:
            return None
        cls = found[0]
    return module, cls


def available(only: list[str] | None = None) -> list[tuple[Entry, Any, type[Any]]]:
    """Return the simulators whose modules exist, in the config flow's vendor order.

    A simulator that fails to import is reported and skipped unless it was asked for by name:
    one unfinished simulator must not take the whole demo down.
    """
    found = []
    for entry in SIMULATORS:
        if only and entry.vendor not in only:
            continue
        try:
            loaded = load(entry)
        except Exception as err:
            if only:
                raise
            print(f"skipping the {entry.vendor} simulator: {err!r}", file=sys.stderr)
            continue
        if loaded is not None:
            found.append((entry, *loaded))
    return found


async def _maybe_await(value: Any) -> Any:
    """Await a coroutine; pass anything else through (a simulator may start synchronously)."""
    return await value if inspect.isawaitable(value) else value


def describe(entry: Entry, module: Any, simulator: Any) -> dict[str, Any]:
    """Return what a user needs to reach a running simulator."""
    return {
        "vendor": entry.vendor,
        "host": getattr(simulator, "host", "127.0.0.1"),
        "port": getattr(simulator, "port", entry.port),
        "username": getattr(module, "DEFAULT_USER", None),
        "password": getattr(module, "DEFAULT_PASSWORD", None),
        "tls": bool(getattr(simulator, "tls", False)),
        "fingerprint": getattr(simulator, "fingerprint", None),
        "options": {
            key: getattr(simulator, key)
            for key in ("rack", "slot")
            if isinstance(getattr(simulator, key, None), int)
        }
        | getattr(simulator, "form_fields", {}),
    }


def show(info: dict[str, Any]) -> str:
    """Return one human-readable block about a running simulator."""
    lines = [f"{info['vendor']:<9} {'https' if info['tls'] else 'tcp/http'} {info['host']}:"]
    lines[0] += str(info["port"])
    if info["username"] is not None:
        lines.append(f"          user {info['username']!r}  password {info['password']!r}")
    if info["fingerprint"]:
        lines.append(f"          certificate SHA-256 {info['fingerprint']}")
    if info["options"]:
        lines.append("          " + "  ".join(f"{k} {v}" for k, v in info["options"].items()))
    return "\n".join(lines)


def _control(
    loop: asyncio.AbstractEventLoop, simulators: list[tuple[Entry, Any]], stop: asyncio.Event
) -> None:
    """Answer "requests" (or "connections") lines on stdin with the counters; stop at its end.

    "connections" counts the client connections (TCP, and TLS handshakes where the simulator
    speaks HTTPS) seen since the start. Runs in a daemon thread: a blocking read there never
    delays the shutdown.
    """

    def answer(what: str) -> None:
        counts = {entry.vendor: _count(sim, what) for entry, sim in simulators}
        print(json.dumps(counts), flush=True)

    for line in sys.stdin:
        if (what := line.strip()) in ("requests", "connections"):
            loop.call_soon_threadsafe(answer, what)
    loop.call_soon_threadsafe(stop.set)


def _count(simulator: Any, what: str) -> int | None:
    """Return a simulator's request or connection count (None where it keeps none)."""
    if what == "connections":
        peers = getattr(simulator, "peers", None)
        return None if peers is None else len(peers)
    return getattr(simulator, "requests", None)


def keep_certificate(simulator: Any, folder: Path, vendor: str) -> None:
    """Serve the certificate kept in folder (made and kept there the first time).

    The demo's entries pin it: a new certificate at every start would look like another device.
    """
    chain_file, key_file = folder / f"{vendor}.pem", folder / f"{vendor}.key"
    if not (chain_file.exists() and key_file.exists()):
        chain, key = make_certificate(simulator.common_name)
        folder.mkdir(parents=True, exist_ok=True)
        key_file.touch(mode=0o600)
        key_file.write_bytes(key)
        chain_file.write_bytes(chain)
    simulator.use_certificate(chain_file.read_bytes(), key_file.read_bytes())


async def _animate(simulators: list[tuple[Entry, Any]], stop: asyncio.Event) -> None:
    """Call `animate(seconds since start)` of the simulators that have it, once a second."""
    movers = [sim for _entry, sim in simulators if callable(getattr(sim, "animate", None))]
    started = time.monotonic()
    while movers and not stop.is_set():
        for sim in movers:
            sim.animate(time.monotonic() - started)
        with contextlib.suppress(TimeoutError):
            await asyncio.wait_for(stop.wait(), 1.0)


async def run(
    only: list[str] | None,
    port: int | None,
    as_json: bool,
    control: bool,
    options: dict[str, dict[str, Any]] | None = None,
    *,
    demo: bool = False,
    certificates: Path | None = None,
) -> int:
    """Start the simulators, report them, and serve until told to stop.

    `options` holds constructor arguments by vendor (the benchmarks ask for bigger memories).
    """
    found = available(only)
    if not found:
        print("no simulator found" + (f" for {', '.join(only)}" if only else ""), file=sys.stderr)
        return 1
    running: list[tuple[Entry, Any]] = []
    stop = asyncio.Event()
    loop = asyncio.get_running_loop()
    for signum in (signal.SIGINT, signal.SIGTERM):
        loop.add_signal_handler(signum, stop.set)
    try:
        for entry, module, cls in found:
            default = getattr(cls, "DEMO_OPTIONS", {}) if demo else {}
            simulator = cls(**(options or {}).get(entry.vendor, default))
            if certificates is not None and getattr(simulator, "tls", False):
                keep_certificate(simulator, certificates, entry.vendor)
                if callable(getattr(simulator, "keep_client_certificate", None)):
                    simulator.keep_client_certificate(certificates)
            await _maybe_await(simulator.start("127.0.0.1", entry.port if port is None else port))
            running.append((entry, simulator))
            info = describe(entry, module, simulator)
            print(json.dumps(info) if as_json else show(info), flush=True)
        if not as_json:
            print("simulators running; Ctrl-C stops them", flush=True)
        if control:
            threading.Thread(target=_control, args=(loop, running, stop), daemon=True).start()
        if demo:
            await _animate(running, stop)
        await stop.wait()
    finally:
        for _entry, simulator in reversed(running):
            with contextlib.suppress(Exception):
                await _maybe_await(simulator.stop())
    return 0


def main() -> int:
    """Parse the command line and run."""
    parser = argparse.ArgumentParser(prog="python -m simulators", description=__doc__)
    parser.add_argument(
        "--only", nargs="+", metavar="VENDOR", help="start only these vendors' simulators"
    )
    parser.add_argument("--port", type=int, help="one port for all (0: any free port)")
    parser.add_argument("--json", action="store_true", help="one JSON line per simulator")
    parser.add_argument(
        "--control",
        action="store_true",
        help="serve until stdin closes; answer 'requests' and 'connections'",
    )
    parser.add_argument("--demo", action="store_true", help="let some values move, once a second")
    parser.add_argument(
        "--certs", type=Path, metavar="DIR", help="keep TLS certificates in DIR across starts"
    )
    args = parser.parse_args()
    settings = {"demo": args.demo, "certificates": args.certs}
    try:
        return asyncio.run(run(args.only, args.port, args.json, args.control, **settings))
    except KeyboardInterrupt:
        return 0


if __name__ == "__main__":
    sys.exit(main())
