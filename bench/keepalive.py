"""Keep-alive: connections a PLC accepts over 10 polls at a 60 s poll interval, per HTTP vendor.

On HTTPS each connection is a TLS handshake, which the S7-200 SMART manual (4.2) calls slow and
costly for the CPU. Two clients are compared: PLC Bridge's own session for the PLC (the entry's,
`plc.http.client_session`), and a plain aiohttp session as Home Assistant shares it (aiohttp's
15 s idle default).

The 60 s between polls are virtual: before each poll, the client's connection pool clock
(`aiohttp.connector.monotonic`) is moved on by the interval, instead of waiting ten minutes.
The simulator in its subprocess keeps an idle connection for 75 s (aiohttp's server default),
longer than the gap; a real PLC that closes idle connections sooner is not modelled here.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
import contextlib
from typing import Any

import aiohttp
import aiohttp.connector

from custom_components.plc_bridge.plc.vendors import client_class

from .poll import VENDORS, Simulator, make_client

POINTS = 10
"""Points per poll: enough for a real request, few enough to stay one request on every vendor."""


@contextlib.contextmanager
def virtual_idle() -> Iterator[Callable[[float], None]]:
    """Let the caller move aiohttp's connection pool clock on by a number of seconds."""
    real = aiohttp.connector.monotonic
    offset = [0.0]

    def moved() -> float:
        return real() + offset[0]

    def idle(seconds: float) -> None:
        offset[0] += seconds

    aiohttp.connector.monotonic = moved
    try:
        yield idle
    finally:
        aiohttp.connector.monotonic = real


async def _connections(vendor: str, shared: bool, interval: float, polls: int) -> dict[str, Any]:
    """Connect, then poll `polls` times `interval` apart; return the connections the PLC saw."""
    cls = client_class(vendor)
    points = [cls.validate_point(point) for point in VENDORS[vendor].points(POINTS)]
    simulator = Simulator(vendor)
    if not await simulator.start():
        return {}
    try:
        async with contextlib.AsyncExitStack() as stack:
            session = await stack.enter_async_context(aiohttp.ClientSession()) if shared else None
            idle = stack.enter_context(virtual_idle())
            client = make_client(vendor, simulator.info, session, interval)
            stack.push_async_callback(client.close)
            await client.connect()
            failed = 0
            for poll in range(polls):
                if poll:
                    idle(interval)
                result = await client.read(points)
                failed += sum(1 for value in result.values.values() if not value.ok)
            return {
                "check": "keepalive",
                "vendor": vendor,
                "https": bool(simulator.info.get("tls")),
                "session": "shared (aiohttp default, 15 s)" if shared else "plc_bridge",
                "poll_interval_s": interval,
                "polls": polls,
                "connections": await simulator.connections(),
                "failed_points": failed,
            }
    finally:
        await simulator.stop()


async def keepalive_rows(
    vendors: list[str], interval: float = 60.0, polls: int = 10
) -> list[dict[str, Any]]:
    """Measure every HTTP vendor with PLC Bridge's session and with a shared one."""
    rows = [
        await _connections(vendor, shared, interval, polls)
        for vendor in vendors
        if client_class(vendor).uses_http
        for shared in (False, True)
    ]
    return [row for row in rows if row]


def keepalive_text(row: dict[str, Any]) -> str:
    """Return one keep-alive row as text."""
    kind = "TLS handshakes" if row["https"] else "TCP connections (plain HTTP)"
    return (
        f"keep-alive ({row['vendor']}, {row['session']} session): connect + {row['polls']} polls"
        f" {row['poll_interval_s']:.0f} s apart took {kind}: {row['connections']}"
        + (f" ({row['failed_points']} point reads failed)" if row["failed_points"] else "")
    )
