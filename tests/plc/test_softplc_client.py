"""SoftPLC client against the WEB.TLM simulator: one POST a poll, writes in one PUT."""

from __future__ import annotations

import pytest

from custom_components.plc_bridge.plc import (
    PlcAddressError,
    PlcProtocolError,
    PlcWriteRefusedError,
    Point,
)
from custom_components.plc_bridge.plc.vendors.softplc import SoftplcClient
from simulators.softplc import SoftplcSimulator

POINTS = {
    "N7:3": 3,
    "N7:5": 5,
    "N7:40": 40,
    "B3:0/1": True,
    "B3/2": False,
    "T4:0.PRE": 4000,
    "T4:0.ACC": 1200,
    "T4:0.DN": False,
    "F8:0": 21.5,
    "I:0": 5,
    "PD9:0.SP": 50.0,
    "important_int": 10,
}


async def test_poll_is_one_post(softplc_reading: tuple[SoftplcSimulator, SoftplcClient]) -> None:
    """Every point in one POST of merged ranges; replies matched under every reading."""
    sim, client = softplc_reading
    before = sim.requests
    result = await client.read([Point(address, "") for address in POINTS])
    assert {p.address: r.value for p, r in result.values.items()} == POINTS
    assert sim.requests - before == 1
    assert client.metrics.last_poll_requests == 1
    assert sim.items[-1] == 8 == SoftplcClient.items_for([Point(a, "") for a in POINTS])


async def test_bad_address_fails_alone(
    softplc_reading: tuple[SoftplcSimulator, SoftplcClient],
) -> None:
    """A bad item fails only its points, however the PLC says so; later polls skip it."""
    softplc_sim, softplc_client = softplc_reading
    points = [Point("N7:98", ""), Point("N7:99", ""), Point("N7:100", ""), Point("N99:0", "")]
    points.append(Point("F8:0", ""))
    result = await softplc_client.read(points)
    values = {p.address: r for p, r in result.values.items()}
    assert values["N7:98"].value == 98
    assert values["N7:99"].value == 99
    assert values["F8:0"].value == 21.5
    for address in ("N7:100", "N99:0"):
        assert isinstance(values[address].error, PlcAddressError)
    assert "N99" in str(values["N99:0"].error)
    before = softplc_sim.requests
    again = await softplc_client.read(points)
    assert softplc_sim.requests - before == 1
    assert {p.address: r.ok for p, r in again.values.items()} == {
        p.address: r.ok for p, r in result.values.items()
    }


async def test_count_past_the_end_truncated(
    softplc_client: SoftplcClient, softplc_sim: SoftplcSimulator
) -> None:
    """A PLC that answers fewer elements than asked fails the points beyond, not the rest."""
    softplc_sim.bad_item = "item"
    softplc_sim.past_end = "truncate"
    sim_file = softplc_sim.files["N", 7]
    del sim_file.words[50:]
    result = await softplc_client.read([Point("N7:45", ""), Point("N7:52", "")])
    values = {p.address: r for p, r in result.values.items()}
    assert values["N7:45"].value == 45
    assert isinstance(values["N7:52"].error, PlcAddressError)


async def test_every_item_refused_fails_the_poll(
    softplc_client: SoftplcClient, softplc_sim: SoftplcSimulator
) -> None:
    """When the PLC refuses every item, the poll fails as a whole."""
    softplc_sim.error_style = "text"
    with pytest.raises(PlcProtocolError):
        await softplc_client.read([Point("N98:0", ""), Point("N99:0", "")])


async def test_writes_in_one_put(
    softplc_client: SoftplcClient, softplc_sim: SoftplcSimulator
) -> None:
    """Words, hex input, floats, structure words and tags go in one PUT; bits read first."""
    values = {
        Point("N7:0", "INT"): -2,
        Point("N7:1", "UINT"): "0xF73D",
        Point("B3:0/2", "BOOL"): True,
        Point("T4:0.PRE", "INT"): 3000,
        Point("F8:1", "REAL"): 1.25,
        Point("PD9:1.KP", "REAL"): 2.5,
        Point("important_int", "INT"): 555,
    }
    before = softplc_sim.requests
    results = await softplc_client.write(values)
    assert all(result.ok for result in results.values()), results
    assert softplc_sim.requests - before == 2  # the bit's word, then the PUT
    put = softplc_sim.bodies[-1]
    assert b'<data ad="N7:0" count="2">0xFFFE 0xF73D</data>' in put
    assert b'<data ad="T4:0.PRE">3000</data>' in put
    assert b'<data ad="important_int" count="1">555</data>' in put
    assert softplc_sim.files["B", 3].words[0] == 0b1110
    assert softplc_sim.files["N", 7].words[10] == 555
    read = await softplc_client.read(list(values))
    assert read.values[Point("N7:1", "UINT")].value == 63293
    assert read.values[Point("N7:0", "INT")].value == -2


async def test_write_refused_fails_alone(
    softplc_client: SoftplcClient, softplc_sim: SoftplcSimulator
) -> None:
    """A refused item of a PUT fails its points; the others are written."""
    results = await softplc_client.write({Point("N7:0", ""): 1, Point("N99:0", ""): 2})
    assert results[Point("N7:0", "")].ok
    assert isinstance(results[Point("N99:0", "")].error, PlcWriteRefusedError)


async def test_write_answered_otherwise(
    softplc_client: SoftplcClient, softplc_sim: SoftplcSimulator
) -> None:
    """A PUT answered with other values than sent is a refused write."""
    softplc_sim.rewrite = lambda body: body.replace(b">\n7\n<", b">\n8\n<")
    results = await softplc_client.write({Point("N7:0", ""): 7})
    assert isinstance(results[Point("N7:0", "")].error, PlcWriteRefusedError)
