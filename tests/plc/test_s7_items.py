"""Items per S7 job: packed to the PDU, fewer once the CPU shows its limit, in every reading.

simulators/s7/READINGS.md, row 1: a CPU that takes fewer items than the PDU carries refuses
the job (0x8500 or 0x8104), answers fewer items, or fails the items past its limit. Every
value must land under its own point whatever the reading, and the count learned is kept.
"""

from __future__ import annotations

from collections.abc import AsyncGenerator
import math

import pytest

from custom_components.plc_bridge.plc import PlcProtocolError, Point, Value
from custom_components.plc_bridge.plc.vendors.s7 import S7Client
from simulators.s7 import S7Simulator

from . import s7_fixtures
from .s7_fixtures import ITEM_READINGS, ConfigFactory, item_reading
from .test_s7_client import VALUES

s7_sim = s7_fixtures.s7_sim
s7_config = s7_fixtures.s7_config
s7_client = s7_fixtures.s7_client

COUNT = 30  # points, each in a DB of its own: no merging, one item each
POINTS = [Point(f"DB{number}.DBW2", "INT") for number in range(1, COUNT + 1)]


@pytest.fixture(params=list(ITEM_READINGS))
async def cpu(request: pytest.FixtureRequest) -> AsyncGenerator[S7Simulator]:
    """A CPU with DB1..DB30, DBn.DBW2 holding n, in each reading of too many items."""
    sim = item_reading(S7Simulator(dbs=dict.fromkeys(range(1, COUNT + 1), 4)), request.param)
    for number in range(1, COUNT + 1):
        sim.set_db(number, 2, number.to_bytes(2, "big"))
    await sim.start()
    yield sim
    await sim.stop()


async def test_every_value_under_its_point(cpu: S7Simulator, s7_config: ConfigFactory) -> None:
    """Whatever the reading, each point gets its own DB's value; later polls keep the count."""
    client = S7Client(s7_config(port=cpu.port))
    per_job = cpu.max_items or COUNT
    try:
        await client.connect()
        reads = []
        for _ in range(3):
            before = cpu.calls["read"]
            result = await client.read(POINTS)
            assert [result.values[point].value for point in POINTS] == list(range(1, COUNT + 1))
            reads.append(cpu.calls["read"] - before)
        assert reads[0] <= 14  # the poll that learns: a few jobs more, once
        assert reads[1:] == [math.ceil(COUNT / per_job)] * 2  # 1 job of 30, or 6 of 5
        assert client.metrics.last_poll_requests == reads[-1]  # the status: once a minute
    finally:
        await client.close()


async def test_every_write_in_place(cpu: S7Simulator, s7_config: ConfigFactory) -> None:
    """Writes learn the count as reads do; every value reaches its own address, once."""
    client = S7Client(s7_config(port=cpu.port))
    values: dict[Point, Value] = {point: -n for n, point in enumerate(POINTS, 1)}
    try:
        await client.connect()
        results = await client.write(values)
        assert all(result.ok for result in results.values())
        assert [cpu.get_db(n, 2, 2) for n in range(1, COUNT + 1)] == [
            (-n).to_bytes(2, "big", signed=True) for n in range(1, COUNT + 1)
        ]
        before = cpu.calls["write"]
        await client.write(values)
        per_job = cpu.max_items or 26  # PDU 480: 12 + 26 * 18 bytes
        assert cpu.calls["write"] - before == math.ceil(COUNT / per_job)
    finally:
        await client.close()


async def test_a_bad_address_ends_a_job(cpu: S7Simulator, s7_config: ConfigFactory) -> None:
    """A missing DB last in a job fails alone; asked again once, not at every poll."""
    client = S7Client(s7_config(port=cpu.port))
    points = [*POINTS, Point("DB99.DBW0", "INT")]  # sorted last: no DB99
    try:
        await client.connect()
        for _ in range(2):
            result = await client.read(points)
            assert [result.values[point].value for point in POINTS] == list(range(1, COUNT + 1))
            assert "no such object" in str(result.values[points[-1]].error)
        before = cpu.calls["read"]
        await client.read(points)
        assert cpu.calls["read"] - before == math.ceil((COUNT + 1) / (cpu.max_items or COUNT + 1))
    finally:
        await client.close()


async def test_packed_to_the_pdu(s7_config: ConfigFactory) -> None:
    """At PDU 960 a job holds 79 address specs: 200 items take 3 reads, not 10 of 20."""
    sim = S7Simulator(pdu_size=960, dbs=dict.fromkeys(range(1, 201), 4))
    await sim.start()
    client = S7Client(s7_config(port=sim.port))
    points = [Point(f"DB{number}.DBW0", "INT") for number in range(1, 201)]
    try:
        await client.connect()
        before = sim.calls["read"]
        assert all(outcome.ok for outcome in (await client.read(points)).values.values())
        assert sim.calls["read"] - before == 3
        assert client.planned_requests(points) == 3
        before = sim.calls["write"]
        assert all(result.ok for result in (await client.write(dict.fromkeys(points, 1))).values())
        assert sim.calls["write"] - before == 4  # 18 bytes an item: 52 a job
    finally:
        await client.close()
        await sim.stop()


async def test_refused_whatever_the_count(s7_sim: S7Simulator, s7_client: S7Client) -> None:
    """PUT/GET off refuses one item too: the poll fails after one item asked alone, and the
    count is not lowered for when access is permitted again."""
    s7_sim.put_get_refused = True
    points = [Point(f"MW{2 * n}", "INT") for n in range(3)] + [Point("DB1.DBW0", "INT")]
    for _ in range(2):
        before = s7_sim.calls["read"]
        with pytest.raises(PlcProtocolError, match="permit PUT/GET"):
            await s7_client.read(points)
        assert s7_sim.calls["read"] - before == 2  # the job, then its first item alone
    s7_sim.put_get_refused = False
    before = s7_sim.calls["read"]
    assert all(outcome.ok for outcome in (await s7_client.read(points)).values.values())
    assert s7_sim.calls["read"] - before == 1


async def test_errors_stay_with_their_points(cpu: S7Simulator, s7_config: ConfigFactory) -> None:
    """Missing DBs and out-of-range words among 30 good items: in every reading, each point
    gets its own value or its own error, at the first poll and after."""
    client = S7Client(s7_config(port=cpu.port))
    bad = {
        Point("DB40.DBW0", "INT"): "no such object",  # no DB40, sorted last
        Point("DB3.DBW4", "INT"): "out of range",  # DB3 has 4 bytes
        Point("MW300", "INT"): "out of range",  # M has 256 bytes; sorted first
    }
    points = [*bad, *POINTS]
    try:
        await client.connect()
        for _ in range(3):
            result = await client.read(points)
            assert [result.values[point].value for point in POINTS] == list(range(1, COUNT + 1))
            for point, message in bad.items():
                assert message in str(result.values[point].error)
    finally:
        await client.close()


async def test_every_type_in_every_reading(cpu: S7Simulator, s7_config: ConfigFactory) -> None:
    """Bits, bytes, T/C, strings (their headers read first) and dates, 35 points written and
    read back under each reading: every value in place."""
    cpu.add_db(1, 512)  # the layout of test_s7_client (V memory is DB1)
    cpu.add_db(3, 300)
    values = {Point(address, data_type): value for address, data_type, value in VALUES}
    cpu.set_db(1, 34, b"\x0c")  # STRING[12]
    client = S7Client(s7_config(port=cpu.port))
    try:
        await client.connect()
        written = await client.write(values)
        assert {point: result.value for point, result in written.items()} == values
        for _ in range(2):
            read = (await client.read(list(values))).values
            assert {point: outcome.value for point, outcome in read.items()} == values
    finally:
        await client.close()
