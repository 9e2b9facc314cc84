"""SoftPLC against every reading of the manual's silences (simulators/softplc/READINGS.md).

Each test runs once per simulator variant (`VARIANTS`): a point shows its own value, or fails
where the client cannot tell the readings apart; never another point's value.
"""

from __future__ import annotations

import contextlib

import pytest

from custom_components.plc_bridge.plc import PlcAddressError, PlcConnectionError, PlcError, Point
from custom_components.plc_bridge.plc.vendors.softplc import SoftplcClient
from simulators.softplc import SoftplcSimulator

from .softplc_fixtures import busy_waits

__all__ = ["busy_waits"]  # a fixture, imported to be found

type Reading = tuple[SoftplcSimulator, SoftplcClient]


def told_apart(sim: SoftplcSimulator, tags: int) -> bool:
    """False where the reading leaves the client no way to place the tags' answers."""
    return sim.tag_reply != "address" or tags < 2


async def test_tags_differing_in_case(softplc_reading: Reading) -> None:
    """pump and Pump go as two items, as typed; each shows its own tag's value."""
    sim, client = softplc_reading
    if sim.tag_case == "exact":
        sim.tags |= {"pump": "N7:20", "Pump": "N7:21"}
        expected = {"pump": 20, "Pump": 21}
    else:  # a case-blind table holds one of them, whichever case is asked
        sim.tags |= {"Pump": "N7:21"}
        expected = {"pump": 21, "Pump": 21}
    points = [Point(name, "INT") for name in expected] + [Point("N7:3", "INT")]
    values = (await client.read(points)).values
    assert b'ad="pump"' in sim.bodies[-1]
    assert b'ad="Pump"' in sim.bodies[-1]
    assert values[Point("N7:3", "INT")].value == 3
    for name, value in expected.items():
        result = values[Point(name, "INT")]
        if told_apart(sim, 2):
            assert result.value == value, (name, result)
        else:
            assert result.value in (None, value), (name, result)


async def test_one_tag_answered_any_way(softplc_reading: Reading) -> None:
    """A tag beside addresses reads whichever way the PLC names its answer."""
    _sim, client = softplc_reading
    points = [Point("important_int", "INT"), Point("N7:3", "INT"), Point("F8:0", "REAL")]
    values = (await client.read(points)).values
    assert [values[point].value for point in points] == [10, 3, 21.5]


async def test_request_forms_sent(softplc_reading: Reading) -> None:
    """I1:3 and O0:2 go as typed, I:5 in the request form I1:5, I1 and S2 (no colon) as typed;
    each value is read from the place the PLC gives it, normalised or not."""
    sim, client = softplc_reading
    sim.files["I", 1].words[:] = [10, 11, 12, 13, 14, 15, 16, 17]
    sim.files["O", 0].words[:] = [20, 21, 22, 23, 24, 25, 26, 27]
    sim.files["S", 2].words[:3] = [30, 31, 32]
    short = 0 if sim.short == "file" else None
    expected = {
        "I1:3": 13,
        "I:5": 15,
        "O0:2": 22,
        "I1": 10 if short == 0 else 11,
        "S2": 30 if short == 0 else 32,
    }
    points = [Point(text, "INT") for text in expected]
    values = (await client.read(points)).values
    body = sim.bodies[-1]
    assert b'ad="I1:3" count="3"' in body
    assert b'ad="O0:2"' in body
    assert b'ad="I1"' in body
    assert b'ad="S2"' in body
    assert b'ad="I:' not in body
    assert b'ad="O:' not in body
    assert {point.address: values[point].value for point in points} == expected
    assert SoftplcClient.validate_point(Point("I1:3", "")).address == "I1:3"


async def test_same_place_twice_never_guessed(softplc_reading: Reading) -> None:
    """I1 (no colon) beside I1:0 and I1:1: where a normalised answer names the same place for
    both items (I1 read as file I1), they fail; otherwise each reads its own value."""
    sim, client = softplc_reading
    sim.files["I", 1].words[:] = [10, 11, 12, 13, 14, 15, 16, 17]
    points = [Point("I1:0", "INT"), Point("I1:1", "INT"), Point("I1", "INT")]
    points.append(Point("N7:3", "INT"))
    values = (await client.read(points)).values
    assert values[points[3]].value == 3
    if sim.normalize and sim.short == "file":
        assert all(isinstance(values[point].error, PlcError) for point in points[:3])
    else:
        own = 10 if sim.short == "file" else 11
        assert [values[point].value for point in points[:3]] == [10, 11, own]


async def test_busy_run_is_no_verdict(softplc_reading: Reading, busy_waits: list[float]) -> None:
    """A run of 503 answers fails that poll in two requests (one resend), and marks no address
    bad: on the first good poll every point is back (a bad one still fails alone)."""
    sim, client = softplc_reading
    good = [Point("N7:1", "INT"), Point("N7:50", "INT"), Point("F8:0", "REAL")]
    bad = Point("N99:0", "INT")
    for run in (2, 3):
        sim.busy.extend([503] * run)
        before = sim.requests
        with pytest.raises(PlcConnectionError, match="503"):
            await client.read([*good, bad])
        assert sim.requests - before == 2
        sim.busy.clear()
        values = (await client.read([*good, bad])).values
        assert [values[point].value for point in good] == [1, 50, 21.5]
        assert isinstance(values[bad].error, PlcAddressError)


async def test_busy_inside_a_search(softplc_reading: Reading, busy_waits: list[float]) -> None:
    """A 503 met while halving around a bad item fails that poll, never the items asked."""
    sim, client = softplc_reading
    good = [Point("N7:1", "INT"), Point("N7:50", "INT"), Point("F8:0", "REAL")]
    bad = Point("N99:0", "INT")
    first = await client.read([*good, bad])
    assert isinstance(first.values[bad].error, PlcAddressError)
    client._probed_at = -float("inf")  # the next poll asks the refused address again
    sim.busy.extend([503, 503])
    sim.busy_after = 1  # the poll's first request is answered, the search meets the 503s
    with contextlib.suppress(PlcConnectionError):  # where the first request was refused
        await client.read([*good, bad])
    sim.busy.clear()
    values = (await client.read([*good, bad])).values
    assert [values[point].value for point in good] == [1, 50, 21.5]
    assert isinstance(values[bad].error, PlcAddressError)


async def test_words_printed_any_way(softplc_reading: Reading) -> None:
    """A word is the same value printed unsigned (63293), signed (-2243) or in hex (0xf73d)."""
    sim, client = softplc_reading
    sim.files["N", 7].words[1] = 0xF73D
    sim.files["O", 0].words[1] = 0x8001
    points = [Point("N7:1", "INT"), Point("N7:1", "UINT"), Point("N7:1", "WORD")]
    points += [Point("O0:1", "INT"), Point("O0:1/15", "BOOL")]
    values = (await client.read(points)).values
    assert [values[point].value for point in points] == [-2243, 63293, 63293, -32767, True]


async def test_writes_as_typed(softplc_reading: Reading) -> None:
    """A PUT carries tags as typed and O3 (no colon) as typed; each result is its own item's."""
    sim, client = softplc_reading
    if sim.tag_case == "exact":
        sim.tags |= {"pump": "N7:20", "Pump": "N7:21"}
    else:
        sim.tags |= {"Pump": "N7:21"}
    values = {Point("pump", "INT"): 5, Point("Pump", "INT"): 6, Point("O3", "INT"): 7}
    values[Point("I1:2", "INT")] = 8
    results = await client.write(values)
    body = b"".join(sim.bodies)  # a refused PUT is sent again in halves (reading 7a)
    assert b'<data ad="pump" count="1">5</data>' in body
    assert b'<data ad="Pump" count="1">6</data>' in body
    assert b'<data ad="O3" count="1">7</data>' in body
    assert b'<data ad="I1:2" count="1">8</data>' in body
    assert results[Point("I1:2", "INT")].value == 8
    assert sim.files["I", 1].words[2] == 8
    if sim.short == "element":
        assert results[Point("O3", "INT")].value == 7
        assert sim.files["O", 0].words[3] == 7
    else:  # O3 is file O3, which the PLC has not
        assert not results[Point("O3", "INT")].ok
    # a case-blind PLC answering both with its own spelling, or with addresses, names two
    # different answers alike: both writes are reported failed, never confirmed by the other
    told = sim.tag_reply == "sent" or (sim.tag_case == "exact" and sim.tag_reply == "table")
    for name, value in {"pump": 5, "Pump": 6}.items():
        result = results[Point(name, "INT")]
        assert result.value in ((value,) if told else (value, None))
    if sim.tag_case == "exact":
        assert sim.files["N", 7].words[20:22] == [5, 6]
