"""Each vendor's pacing as its manual advises, the points a paced read takes in a time, its poll.

No `no_pacing` marker here: these tests see the pacing the vendors ship with.
"""

from __future__ import annotations

import asyncio

import pytest

from custom_components.plc_bridge.plc import Point, PointResult
from custom_components.plc_bridge.plc.vendors import client_class, implemented
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from simulators.s7_smart import S7SmartSimulator

ADVISED = {
    "s7_smart": 1.0,  # "It is recommended to call less than once a second" (manual 4.2)
    "tecomat": 0.0,  # the TecoApi manual advises no request rate
    "plcnext": 0.0,  # the REST notes: "No rate limit documented"
    "softplc": 0.0,  # WEB.TLM names connections (over 50), no request rate
    "s7": 0.0,  # the S7comm notes advise none; the negotiated PDU bounds a request
    "logo": 0.0,  # LOGO! speaks S7comm on the S7 transport: no request rate advised either
}
"""Seconds between requests each vendor's documentation advises (0: it advises none)."""


def test_every_vendor_has_its_advised_pacing_pinned() -> None:
    """Every vendor the integration implements is pinned below."""
    assert set(ADVISED) == set(implemented())


@pytest.mark.parametrize(("vendor", "seconds"), ADVISED.items())
def test_vendor_paced_as_its_manual_advises(vendor: str, seconds: float) -> None:
    """A vendor's client paces its requests as its manual advises, and plans its polls so."""
    cls = client_class(vendor)
    assert cls.request_interval == seconds
    assert cls.min_scan_interval(words(64)) == seconds * cls.requests_for(words(64))


async def test_s7_smart_requests_are_a_second_apart(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    """The S7-200 SMART's transport waits out its second: 3 reads take 2 s of pacing at least."""
    loop = asyncio.get_running_loop()
    started = loop.time()
    await s7_smart_client.read(words(3 * 32))
    assert loop.time() - started >= 2 * ADVISED["s7_smart"] * 0.9


def words(count: int) -> list[Point]:
    """Return `count` V words, one S7-200 SMART read node each."""
    return [Point(f"VW{2 * index}", "signed") for index in range(count)]


@pytest.mark.parametrize(
    ("seconds", "points"),
    [(0.5, 1), (1.0, 32), (2.0, 64), (31.0, 992), (32.0, 1000), (100.0, 1000)],
)
def test_points_read_within(seconds: float, points: int) -> None:
    """At one request a second, 32 nodes a request: the first points one read takes in time."""
    assert S7SmartClient.points_read_within(words(1000), seconds) == points
    assert S7SmartClient.min_scan_interval(words(1000)) == 32.0


@pytest.mark.parametrize("vendor", ["tecomat", "plcnext", "softplc", "s7"])
def test_unpaced_vendors_read_everything_at_once(vendor: str) -> None:
    """A vendor that paces no requests reads every point in the first poll."""
    cls = client_class(vendor)
    assert cls.points_read_within(words(1000), 0.0) == 1000


async def test_each_request_handed_on_as_it_returns(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    """70 points are 3 paced requests: each one's results go to `on_results` as it returns."""
    reads = s7_smart_sim.calls["read"]
    handed: list[tuple[int, dict[Point, PointResult]]] = []
    result = await s7_smart_client.read(
        words(70), on_results=lambda values: handed.append((s7_smart_sim.calls["read"], values))
    )
    assert [(sent - reads, len(values)) for sent, values in handed] == [(1, 32), (2, 32), (3, 6)]
    assert {p: r for _sent, values in handed for p, r in values.items()} == result.values
