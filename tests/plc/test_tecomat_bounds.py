"""Arrays whose first index is not 0 (ARRAY[1..5], ARRAY[1..2, 1..3], ARRAY[-2..2]): issue 23.

5.2 asks PUBLIC_API arrays to start at 0; IEC 61131-3 and Mosaic allow any first index, and a
JSON array does not say it (simulators/tecomat/READINGS.md row 18). Every reading is run: how
elements are answered (`array_answers`), how a whole array is (`whole_arrays`), and whether
GetList declares types (`list_types`). A value is never shown under another element's index.
"""

from __future__ import annotations

from typing import Any

import pytest

from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient
from custom_components.plc_bridge.plc.vendors.tecomat.browse import first_indices
from simulators.tecomat import TecomatSimulator
from simulators.tecomat.answers import ARRAY_ANSWERS
from simulators.tecomat.program import bounded_arrays
from simulators.tecomat.values import WHOLE_ARRAYS

ONE_D = [Point(f"arrB[{index}]", "INT") for index in (1, 2, 5)] + [
    Point(f"arrN[{index}]", "INT") for index in (-2, 0, 2)
]
MEMBER = [Point(f"rec.arrS[{index}]", "INT") for index in (1, 3)]
TWO_D = [Point(address, "INT") for address in ("arrC[1][1]", "arrC[2][3]", "arrC[1, 2]")]
POINTS = [*ONE_D, *MEMBER, *TWO_D, Point("plcName", "STRING")]
SURE = {"keyed", "objects", "compact"}
"""Element answers that name or order exactly the asked: every point reads."""


@pytest.fixture
def sim(tecomat_sim: TecomatSimulator) -> TecomatSimulator:
    """The simulator with the arrays of simulators.tecomat.program.bounded_arrays."""
    tecomat_sim.variables |= bounded_arrays()
    return tecomat_sim


def held(sim: TecomatSimulator, point: Point) -> Any:
    """Return what the PLC holds at a point."""
    return sim.get(point.address.replace(" ", ""))


@pytest.mark.parametrize("fits", [True, False], ids=["whole", "too-big"])
@pytest.mark.parametrize("whole_arrays", WHOLE_ARRAYS)
@pytest.mark.parametrize("shape", ARRAY_ANSWERS)
async def test_elements_show_their_own_values(
    sim: TecomatSimulator, tecomat_client: TecomatClient, shape: str, whole_arrays: str, fits: bool
) -> None:
    """Several elements polled together: each its own value, or failed; never a neighbour's.

    Before: arrB[1] showed 20 and arrB[2] 30 (the array read whole, indexed from 0), arrB[5]
    failed, and arrN[-2] was refused as an address.
    """
    sim.array_answers, sim.whole_arrays = shape, whole_arrays
    if not fits:
        sim.max_variables = 4  # arrB (5 items) and arrC (6) are too big to answer whole
    for _ in range(2):  # the second poll uses what the first learned
        result = await tecomat_client.read(POINTS)
        for point in POINTS:
            outcome = result.values[point]
            if outcome.ok:
                assert outcome.value == held(sim, point), point.address
            else:
                assert shape not in SURE, (point.address, outcome.error)
                assert shape != "flat" or point in TWO_D, (point.address, outcome.error)
    if shape in SURE:
        assert all(outcome.ok for outcome in result.values.values())


async def test_the_reported_pair(sim: TecomatSimulator, tecomat_client: TecomatClient) -> None:
    """The issue's case: arrB[1] and arrB[2] polled together show 10 and 20."""
    first, second = Point("arrB[1]", "INT"), Point("arrB[2]", "INT")
    result = await tecomat_client.read([first, second])
    assert (result.values[first].value, result.values[second].value) == (10, 20)


@pytest.mark.parametrize("whole_arrays", WHOLE_ARRAYS)
@pytest.mark.parametrize("shape", ARRAY_ANSWERS)
async def test_write_read_back_stays_at_its_index(
    sim: TecomatSimulator, tecomat_client: TecomatClient, shape: str, whole_arrays: str
) -> None:
    """Writing arrB[2] reads back arrB[2]; arrB[1] keeps its own value.

    Before: after writing arrB[2], arrB[1]'s entity showed the written value.
    """
    sim.array_answers, sim.whole_arrays = shape, whole_arrays
    first, second = Point("arrB[1]", "INT"), Point("arrB[2]", "INT")
    written = await tecomat_client.write({second: 99})
    assert written[second].ok, written[second].error
    assert written[second].value in (99, None)  # None: not read back (no index in the answer)
    assert sim.get("arrB[2]") == 99
    assert sim.get("arrB[1]") == 10
    result = await tecomat_client.read([first, second])
    for point, value in ((first, 10), (second, 99)):
        assert result.values[point].value in (value, None)
        if shape in SURE:
            assert result.values[point].value == value


DECLARED = [*ONE_D, *TWO_D]
"""Arrays GetList declares with `list_types` (rec.arrS lies in a structure: not declared)."""


@pytest.mark.parametrize("fits", [True, False], ids=["whole", "too-big"])
@pytest.mark.parametrize("whole_arrays", WHOLE_ARRAYS)
@pytest.mark.parametrize("shape", ARRAY_ANSWERS)
async def test_declared_bounds_place_every_list(
    sim: TecomatSimulator, tecomat_client: TecomatClient, shape: str, whole_arrays: str, fits: bool
) -> None:
    """GetList declares ARRAY[1..5], [1..2, 1..3], [-2..2]: polls index lists from them.

    No corner is probed for a declared array (arrB[0], arrN[0] are never asked), GetList is
    asked once a program. Before: lists answered to these arrays failed every point.
    """
    sim.array_answers, sim.whole_arrays, sim.list_types = shape, whole_arrays, True
    if not fits:
        sim.max_variables = 4
    for _ in range(2):
        result = await tecomat_client.read(POINTS)
        for point in DECLARED:
            outcome = result.values[point]
            if shape == "flat" and point in TWO_D and not fits:
                assert not outcome.ok, point.address  # N-D leaves of elements in a flat list
            else:
                assert outcome.value == held(sim, point), (point.address, outcome.error)
        for point in MEMBER:  # not declared, from 1: placed only where the answer names it
            assert result.values[point].value in (held(sim, point), None), point.address
    assert sim.calls["GetList"] <= 1  # asked when a list needs a first index, once
    assert not any(corner in uri for uri in sim.uris for corner in ("arrB[0]", "arrN[0]&"))


@pytest.mark.parametrize("whole_arrays", WHOLE_ARRAYS)
@pytest.mark.parametrize("shape", ARRAY_ANSWERS)
async def test_declared_bounds_read_back_a_write(
    sim: TecomatSimulator, tecomat_client: TecomatClient, shape: str, whole_arrays: str
) -> None:
    """Writing arrB[2] of a declared ARRAY[1..5] reads back 99 in every answer shape.

    Before: a list answered to the read-back (`whole`, `partial`) left it not read back.
    """
    sim.array_answers, sim.whole_arrays, sim.list_types = shape, whole_arrays, True
    second = Point("arrB[2]", "INT")
    written = await tecomat_client.write({second: 99})
    assert (written[second].value, written[second].error) == (99, None)
    assert sim.get("arrB[1]") == 10


BROWSED = {
    "arrB": [f"arrB[{index}]" for index in range(1, 6)],
    "arrC": [f"arrC[{i}][{j}]" for i in (1, 2) for j in (1, 2, 3)],
    "arrN": [f"arrN[{index}]" for index in range(-2, 3)],
    "rec.arrS": [f"rec.arrS[{index}]" for index in range(1, 4)],
}


@pytest.mark.parametrize("list_types", [False, True], ids=["names-only", "declared"])
@pytest.mark.parametrize("whole_arrays", WHOLE_ARRAYS)
@pytest.mark.parametrize("shape", ["keyed", "whole", "flat"])
async def test_browse_offers_exactly_the_plcs_elements(
    sim: TecomatSimulator,
    tecomat_client: TecomatClient,
    shape: str,
    whole_arrays: str,
    list_types: bool,
) -> None:
    """The pick list offers each element at its own index, or the array as unlisted.

    Before: arrB[0] was offered (the PLC has none) and arrB[5] hidden.
    """
    sim.array_answers, sim.whole_arrays, sim.list_types = shape, whole_arrays, list_types
    offered = {item.address for item in await tecomat_client.browse()}
    for array, elements in BROWSED.items():
        listed = sorted(address for address in offered if address.startswith(array + "["))
        if listed:
            assert listed == sorted(elements), array
        else:  # no first index given (GetList) nor confirmed (0, 1): never guessed
            assert array in tecomat_client.unlisted
            assert (array, whole_arrays, list_types) == ("arrN", "list", False)
    assert "arr1[0]" in offered  # arrays from 0 as before
    result = await tecomat_client.read([Point(address, "INT") for address in BROWSED["arrC"]])
    values = [outcome.value for outcome in result.values.values()]
    assert values == [11, 12, 13, 21, 22, 23]  # the bounds browse confirmed index the array


def test_first_indices_of_a_declaration() -> None:
    """The IEC declarations GetList may give (READINGS.md row 18)."""
    assert first_indices("ARRAY [1..5] OF INT") == (1,)
    assert first_indices("array[1..2, 0..3] of REAL") == (1, 0)
    assert first_indices("ARRAY[1..2] OF ARRAY[-3..3] OF INT") == (1, -3)
    assert first_indices("INT") is None
    assert first_indices("ARRAY [a..b] OF INT") is None
