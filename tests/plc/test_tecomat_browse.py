"""Browsing variables larger than one answer, and types the PLC does not declare (issue 10)."""

from __future__ import annotations

import math

import pytest

from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient
from custom_components.plc_bridge.plc.vendors.tecomat.browse import array_elements
from custom_components.plc_bridge.plc.vendors.tecomat.paths import VariablePath
from simulators.tecomat import TecomatSimulator
from simulators.tecomat.answers import ARRAY_ANSWERS
from simulators.tecomat.values import Var

BIG = 300
"""Elements of the big array: more than two answers of a CP-1xxx (128 items) hold."""


@pytest.fixture
def big_program(tecomat_sim: TecomatSimulator) -> TecomatSimulator:
    """Add an INT array of 300, a 20x20 REAL matrix and a 200-member structure."""
    tecomat_sim.variables["big"] = [Var("INT", index - 150) for index in range(BIG)]
    tecomat_sim.variables["matrix"] = [
        [Var("REAL", row + column / 100) for column in range(20)] for row in range(20)
    ]
    tecomat_sim.variables["recipe"] = {f"step{index}": Var("INT", index) for index in range(200)}
    tecomat_sim.variables["precise"] = Var("LREAL", 12345.678901)
    return tecomat_sim


@pytest.mark.parametrize("shape", ARRAY_ANSWERS)
async def test_arrays_larger_than_an_answer_are_listed(
    big_program: TecomatSimulator, tecomat_client: TecomatClient, shape: str
) -> None:
    """Every element of an array too big to read whole is offered, at its own index.

    Before: browse left out every variable the PLC refused to answer whole (413.004).
    """
    big_program.array_answers = shape
    before = big_program.requests
    items = {item.address: item for item in await tecomat_client.browse()}
    spent = big_program.requests - before
    assert "big[300]" not in items
    if shape in ("whole", "partial"):  # a list longer than asked places no element (row 18)
        assert "big[299]" in tecomat_client.unlisted
        return
    assert [f"big[{index}]" in items for index in range(BIG)] == [True] * BIG
    assert sum(1 for address in items if address.startswith("matrix[")) == 400
    assert tecomat_client.unlisted == ["recipe"]
    # 66 requests for the whole program: GetList, the packed reads, ~2·log2(N) length probes
    # per big array, then its elements packed into URIs of 256 characters (about 25 a request),
    # and one probe of each array read whole (its first and last elements: READINGS.md 18).
    assert spent <= 80
    values = await tecomat_client.read(
        [Point(f"big[{index}]", items[f"big[{index}]"].data_type) for index in (0, 127, 299)]
    )
    assert [result.value for result in values.values.values()] == [-150, -23, 149]


@pytest.mark.parametrize("shape", ARRAY_ANSWERS)
async def test_whole_array_spread_over_requests(
    big_program: TecomatSimulator, tecomat_client: TecomatClient, shape: str
) -> None:
    """All 300 elements as points: several requests, each element its own value, or failed.

    A list longer than the elements asked (the whole array, or one padded) says nothing of the
    array's first index (READINGS.md row 18): those points fail, never shifted.
    """
    big_program.array_answers = shape
    points = [Point(f"big[{index}]", "INT") for index in range(BIG)]
    result = await tecomat_client.read(points)
    assert tecomat_client.metrics.last_poll_requests > 1
    for index, point in enumerate(points):
        outcome = result.values[point]
        if outcome.ok:
            assert outcome.value == index - 150
        else:
            assert shape in ("whole", "partial")
            assert "cannot be told apart" in str(outcome.error)
    if shape not in ("whole", "partial"):
        assert all(outcome.ok for outcome in result.values.values())


async def test_every_type_offered_is_marked_as_guessed(
    big_program: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    """TecoApi declares no type: each is a guess, and a value no REAL prints is an LREAL."""
    items = {item.address: item for item in await tecomat_client.browse()}
    assert all(item.guessed for item in items.values())
    assert items["precise"].data_type == "LREAL"
    assert items["plcData.varReal"].data_type == "REAL"
    result = await tecomat_client.read([Point("precise", "LREAL")])
    assert result.values[Point("precise", "LREAL")].value == 12345.678901


async def test_array_length_costs_log_requests(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    """The length of a 5,000-element array is found in about 2·log2(5000) = 25 probes."""
    tecomat_sim.variables["huge"] = [Var("BOOL", False) for _ in range(5000)]
    api = tecomat_client._teco()
    before = tecomat_sim.requests
    elements = await array_elements(api, VariablePath(("huge",)))
    assert [element.text for element in elements[:2]] == ["huge[0]", "huge[1]"]
    assert len(elements) == 5000
    assert tecomat_sim.requests - before <= 2 * math.ceil(math.log2(5000)) + 1
    assert await array_elements(api, VariablePath(("plcData",))) == []  # a structure
