"""SoftPLC answering 503: a read is sent again once after the wait asked, a write never twice.

Each test runs against every reading of row 14 of simulators/softplc/READINGS.md (the
Retry-After a busy answer carries: none, seconds, an HTTP-date), `softplc_busy`.
"""

from __future__ import annotations

import pytest

from custom_components.plc_bridge.plc import PlcConnectionError, PlcWriteRefusedError, Point
from custom_components.plc_bridge.plc.vendors.softplc import SoftplcClient
from simulators.softplc import SoftplcSimulator

from .softplc_fixtures import busy_waits, expected_wait, softplc_busy

__all__ = ["busy_waits", "softplc_busy"]  # fixtures, imported to be found

type Busy = tuple[SoftplcSimulator, SoftplcClient]
POINTS = [Point("N7:1", "INT"), Point("N7:50", "INT"), Point("F8:0", "REAL")]
VALUES = [1, 50, 21.5]


def puts(sim: SoftplcSimulator) -> int:
    """Return how many PUT bodies the simulator has seen (a PUT carries values)."""
    return sum(1 for body in sim.bodies if b"</data>" in body)


async def test_one_busy_answer_costs_no_poll(softplc_busy: Busy, busy_waits: list[float]) -> None:
    """One 503: the read is sent again after the wait asked (or a short back-off), and shows
    every value. Before: the poll failed."""
    sim, client = softplc_busy
    sim.busy.append(503)
    before = sim.requests
    values = (await client.read(POINTS)).values
    assert [values[point].value for point in POINTS] == VALUES
    assert sim.requests - before == 2
    least, most = expected_wait(sim)
    assert len(busy_waits) == 1
    assert least - 0.5 <= busy_waits[0] <= most  # measured from the answer, a moment ago


async def test_busy_twice_fails_that_poll_only(softplc_busy: Busy, busy_waits: list[float]) -> None:
    """Two 503 in a row: that poll fails after two requests (never a third), the next one reads
    (after the wait the last answer asked, if any)."""
    sim, client = softplc_busy
    sim.busy.extend([503, 503])
    before = sim.requests
    with pytest.raises(PlcConnectionError, match="503"):
        await client.read(POINTS)
    assert sim.requests - before == 2
    values = (await client.read(POINTS)).values
    assert [values[point].value for point in POINTS] == VALUES
    asked = 1 if sim.busy_retry == "none" else 2
    assert len(busy_waits) == asked


async def test_a_wait_longer_than_a_poll_is_not_waited(
    softplc_busy: Busy, busy_waits: list[float]
) -> None:
    """A Retry-After longer than the poll interval: no resend, and no read is sent before it
    ends; a busy answer naming none is sent again after the short back-off."""
    sim, client = softplc_busy
    sim.busy_wait = 120  # the client polls every 5 s
    sim.busy.append(503)
    before = sim.requests
    if sim.busy_retry == "none":
        values = (await client.read(POINTS)).values
        assert [values[point].value for point in POINTS] == VALUES
        assert sim.requests - before == 2
        return
    with pytest.raises(PlcConnectionError, match="503"):
        await client.read(POINTS)
    assert sim.requests - before == 1
    with pytest.raises(PlcConnectionError, match="left alone"):
        await client.read(POINTS)
    assert sim.requests - before == 1
    assert busy_waits == []


@pytest.mark.parametrize("acts", [False, True], ids=["not-written", "written-anyway"])
async def test_busy_write_is_never_sent_twice(
    softplc_busy: Busy, busy_waits: list[float], acts: bool
) -> None:
    """A PUT answered 503 is reported not written and never sent again; the next poll shows
    what the PLC holds (a firmware that wrote all the same: the written value)."""
    sim, client = softplc_busy
    sim.busy_acts = acts
    point = Point("N7:5", "INT")
    sim.busy.append(503)
    with pytest.raises(PlcWriteRefusedError, match="503"):
        await client.write({point: 42})
    assert puts(sim) == 1
    assert busy_waits == []
    values = (await client.read([point])).values
    assert values[point].value == (42 if acts else 5)


async def test_gateway_timeout_on_a_write_is_no_refusal(
    softplc_busy: Busy, busy_waits: list[float]
) -> None:
    """A 504 (a gateway between) to a PUT: the PLC may have written; a connection error, never
    sent again, never called refused."""
    sim, client = softplc_busy
    sim.busy.append(504)
    with pytest.raises(PlcConnectionError, match="504") as caught:
        await client.write({Point("N7:5", "INT"): 42})
    assert not isinstance(caught.value, PlcWriteRefusedError)
    assert puts(sim) == 1
    assert busy_waits == []


async def test_a_bit_write_reads_its_word_through_a_503(
    softplc_busy: Busy, busy_waits: list[float]
) -> None:
    """The read of a bit's word meets a 503: it is sent again, and the bit is written."""
    sim, client = softplc_busy
    sim.files["B", 3].words[2] = 0b1000
    sim.busy.append(503)
    results = await client.write({Point("B3:2/0", "BOOL"): True})
    assert results[Point("B3:2/0", "BOOL")].value is True
    assert sim.files["B", 3].words[2] == 0b1001
    assert len(busy_waits) == 1
