"""How many points a paced vendor reads within a time, and the poll that pacing allows."""

from __future__ import annotations

import pytest

from custom_components.plc_bridge.plc import Point, PointResult
from custom_components.plc_bridge.plc.vendors import client_class
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from simulators.s7_smart import S7SmartSimulator


def words(count: int) -> list[Point]:
    """Return `count` V words, one S7-200 SMART read node each."""
    return [Point(f"VW{2 * index}", "signed") for index in range(count)]


@pytest.mark.parametrize(
    ("seconds", "points"),
    [(0.5, 1), (1.0, 32), (2.0, 64), (31.0, 992), (32.0, 1000), (100.0, 1000)],
)
def test_points_read_within(monkeypatch: pytest.MonkeyPatch, seconds: float, points: int) -> None:
    """At one request a second, 32 nodes a request: the first points one read takes in time."""
    monkeypatch.setattr(S7SmartClient, "request_interval", 1.0)
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
    await s7_smart_client.read(words(70))  # without a callback, as before
    assert s7_smart_sim.calls["read"] == reads + 6
