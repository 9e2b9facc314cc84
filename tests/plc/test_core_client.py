"""The vendor-neutral client base: poll metrics, value checks, the vendor registry."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from datetime import datetime

import pytest

from custom_components.plc_bridge.plc import (
    ConnectionConfig,
    DeviceInfo,
    Footprint,
    PlcClient,
    PlcConnectionError,
    PlcValueError,
    Point,
    PointResult,
    ReadResult,
    Value,
)
from custom_components.plc_bridge.plc.codec import check_integer
from custom_components.plc_bridge.plc.vendors import VENDORS, client_class, implemented


class FakeClient(PlcClient):
    """A vendor that answers from a dict, counting a request per poll."""

    vendor = "fake"
    default_port = 1
    data_types = ("INT",)
    max_points_per_request = 2
    request_interval = 1.5
    fail = False

    @classmethod
    def validate_point(cls, point: Point) -> Point:
        return point

    @classmethod
    def validate_value(cls, point: Point, value: Value) -> Value:
        return check_integer(value, 0, 10)

    async def connect(self) -> DeviceInfo:
        return DeviceInfo(vendor="fake", model="Fake")

    async def _read(self, points: Sequence[Point], *, poll: bool) -> ReadResult:
        self.metrics.requests += self.requests_for(points)
        if self.fail:
            raise PlcConnectionError("down")
        return ReadResult(values={p: PointResult(value=1) for p in points})

    async def _write(self, values: Mapping[Point, Value]) -> dict[Point, PointResult]:
        return {p: PointResult(value=v) for p, v in values.items()}

    async def read_clock(self) -> datetime:
        raise NotImplementedError

    async def set_clock(self, when: datetime) -> None:
        raise NotImplementedError

    async def close(self) -> None:
        await self._close_own_session()


async def test_read_counts_poll_metrics() -> None:
    client = FakeClient(ConnectionConfig(host="h", port=1))
    points = [Point(f"A{i}", "INT") for i in range(5)]
    result = await client.read(points)
    assert all(r.ok for r in result.values.values())
    assert client.metrics.last_poll_requests == 3 == client.requests_for(points)
    client.fail = True
    with pytest.raises(PlcConnectionError):
        await client.read(points)
    assert client.metrics.as_dict()["errors"] == 1
    assert client.metrics.polls == 2


async def test_write_checks_values_before_sending() -> None:
    client = FakeClient(ConnectionConfig(host="h", port=1))
    assert (await client.write({Point("A", "INT"): "7"}))[Point("A", "INT")].value == 7
    with pytest.raises(PlcValueError):
        await client.write({Point("A", "INT"): 11})


async def test_own_session_closed() -> None:
    client = FakeClient(ConnectionConfig(host="h", port=1))
    session = client.session
    assert client.session is session
    await client.close()
    assert session.closed


def test_scan_interval_follows_request_count() -> None:
    assert FakeClient.requests_for([]) == 0
    assert FakeClient.min_scan_interval([Point(str(i), "INT") for i in range(5)]) == 4.5
    assert FakeClient.min_scan_interval([]) == 1.5


def test_registry() -> None:
    assert VENDORS == ("s7_smart", "tecomat", "plcnext", "softplc", "s7", "logo")
    with pytest.raises(KeyError):
        client_class("nope")
    for vendor in implemented():
        assert client_class(vendor).vendor == vendor
    missing = [v for v in VENDORS if v not in implemented()]
    for vendor in missing:
        with pytest.raises(KeyError):
            client_class(vendor)


def test_footprint_default_is_the_name_and_overlap_needs_shared_data() -> None:
    """By default a point covers its name as typed; ranges of one area overlap when they meet."""
    assert FakeClient.footprint(Point("a", "INT")) == Footprint("a", 0, 1)
    assert FakeClient.address_writable(Point("a", "INT"))
    word = Footprint("V", 100, 102)
    assert word.overlaps(Footprint("V", 101, 102))
    assert not word.overlaps(Footprint("V", 102, 103))
    assert not word.overlaps(Footprint("M", 100, 102))
