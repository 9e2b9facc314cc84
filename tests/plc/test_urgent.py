"""Urgent requests (`plc.urgent()`): they go before waiting requests and wait out no pacing."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncGenerator, Callable

import aiohttp
from aiohttp import web
import pytest

from custom_components.plc_bridge.plc import ClientMetrics, ConnectionConfig, Point, urgent
from custom_components.plc_bridge.plc.http import HttpTransport
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from simulators.base import HttpSimulator
from simulators.s7_smart import S7SmartSimulator
from tests.loopback import ConfigFactory, connected, running

GENEROUS = 10.0
"""Seconds an urgent request may take at most here: far less than the pacing it skips."""


class OrderSimulator(HttpSimulator):
    """Notes the body of every request in the order they arrive; /hold waits until released."""

    def __init__(self) -> None:
        """Start with nothing noted and /hold held."""
        super().__init__()
        self.order: list[str] = []
        self.released = asyncio.Event()

    def build_app(self, app: web.Application) -> None:
        """Add /note and /hold."""

        async def note(request: web.Request) -> web.Response:
            self.order.append(await request.text())
            return web.Response(text="ok")

        async def hold(request: web.Request) -> web.Response:
            self.order.append(await request.text())
            await self.released.wait()
            return web.Response(text="ok")

        app.router.add_post("/note", note)
        app.router.add_post("/hold", hold)


@pytest.fixture
async def order_sim() -> AsyncGenerator[OrderSimulator]:
    """The order-noting server on loopback."""
    async with running(OrderSimulator()) as sim:
        yield sim


@pytest.fixture
async def session() -> AsyncGenerator[aiohttp.ClientSession]:
    """A plain aiohttp session."""
    async with aiohttp.ClientSession() as http:
        yield http


def transport(
    session: aiohttp.ClientSession, sim: OrderSimulator, interval: float
) -> HttpTransport:
    """A transport to the order-noting server, pacing `interval` seconds between requests."""
    config = ConnectionConfig(host="127.0.0.1", port=sim.port, timeout=GENEROUS * 2)
    return HttpTransport(config, session, ClientMetrics(), request_interval=interval)


async def send(link: HttpTransport, body: str, *, path: str = "/note", now: bool = False) -> None:
    """Send one request, urgent when `now`."""
    if now:
        with urgent():
            await link.request("POST", path, data=body)
    else:
        await link.request("POST", path, data=body)


async def until(condition: Callable[[], bool]) -> None:
    """Let the loop run until `condition()` holds (a generous bound, never a timed assert)."""
    async with asyncio.timeout(GENEROUS):
        while True:
            if condition():
                return
            await asyncio.sleep(0.01)


async def test_urgent_goes_before_waiting_requests(
    session: aiohttp.ClientSession, order_sim: OrderSimulator
) -> None:
    """Two requests wait behind one in flight; an urgent one sent after them goes first."""
    link = transport(session, order_sim, 0.0)
    held = asyncio.create_task(send(link, "in flight", path="/hold"))
    await until(lambda: order_sim.order == ["in flight"])
    waiting = [asyncio.create_task(send(link, name)) for name in ("second", "third")]
    await asyncio.sleep(0.05)  # both queue up for the transport
    first = asyncio.create_task(send(link, "urgent", now=True))
    await asyncio.sleep(0.05)
    assert order_sim.order == ["in flight"]  # the urgent one still waits for the one in flight
    order_sim.released.set()
    await asyncio.gather(held, first, *waiting)
    assert order_sim.order == ["in flight", "urgent", "second", "third"]


async def test_urgent_skips_the_pacing_wait(
    session: aiohttp.ClientSession, order_sim: OrderSimulator
) -> None:
    """At one request a minute, an urgent request right after another goes at once; others wait."""
    link = transport(session, order_sim, 60.0)
    await send(link, "first")
    async with asyncio.timeout(GENEROUS):
        await send(link, "urgent", now=True)
    paced = asyncio.create_task(send(link, "paced"))
    await asyncio.sleep(0.2)
    assert order_sim.order == ["first", "urgent"]  # the next one still waits out the pacing
    paced.cancel()
    with pytest.raises(asyncio.CancelledError):
        await paced
    async with asyncio.timeout(GENEROUS):  # a cancelled wait gives its turn back
        await send(link, "urgent again", now=True)
    assert order_sim.order == ["first", "urgent", "urgent again"]


def words(count: int) -> list[Point]:
    """Return `count` V words, one S7-200 SMART read node each."""
    return [Point(f"VW{2 * index}", "signed") for index in range(count)]


async def test_urgent_write_overtakes_a_paced_poll(
    s7_smart_sim: S7SmartSimulator,
    s7_smart_config: ConfigFactory,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A poll of 4 requests a second apart: an urgent write goes right after the one in flight.

    Counted with the simulator: when the write returns, the poll has sent one read, not two
    or more, so the write neither waited for the poll's pacing nor for its next request.
    """
    monkeypatch.setattr(S7SmartClient, "request_interval", 1.0)
    async with connected(S7SmartClient(s7_smart_config())) as client:
        reads = s7_smart_sim.calls["read"]
        poll = asyncio.create_task(client.read(words(4 * 32)))
        await until(lambda: s7_smart_sim.calls["read"] == reads + 1)
        async with asyncio.timeout(GENEROUS):
            with urgent():
                results = await client.write({Point("VW1000", "signed"): 7})
        assert all(result.ok for result in results.values())
        assert s7_smart_sim.calls["read"] == reads + 1
        assert s7_smart_sim.get("VW1000") == 7
        result = await poll
        assert s7_smart_sim.calls["read"] == reads + 4
        assert all(outcome.ok for outcome in result.values.values())
