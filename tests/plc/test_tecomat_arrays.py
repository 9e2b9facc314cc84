"""Array elements in every answer shape: never a value under another point's index (issues 10, 19).

The spec shows arrays only whole (5.2). Each shape a PLC may answer elements in is a simulator
switch (simulators/tecomat/READINGS.md, "array answers"); the client is run against all of them.
"""

from __future__ import annotations

from typing import Any

import pytest

from custom_components.plc_bridge.plc import PlcAddressError, Point
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient
from custom_components.plc_bridge.plc.vendors.tecomat.arrays import answered
from custom_components.plc_bridge.plc.vendors.tecomat.paths import parse_path
from simulators.tecomat import TecomatSimulator
from simulators.tecomat.answers import ARRAY_ANSWERS, ELEMENT_SPELLINGS
from simulators.tecomat.values import Var

ONE_DIMENSION = [Point(f"arr1[{index}]", "STRING") for index in (1, 4)] + [
    Point(f"myObject.interests[{index}]", "STRING") for index in (0, 2)
]
SEVERAL = (
    [Point(f"arr2[{row}][{column}]", "REAL") for row, column in ((1, 1), (1, 3), (2, 0))]
    + [Point("arr2[0, 2]", "REAL")]
    + [
        Point(f"arr3[{i}][{j}][{k}]", "BYTE")
        for i, j, k in ((0, 1, 2), (1, 0, 3), (1, 2, 0), (1, 2, 3), (0, 2, 1))
    ]
)
POINTS = [*ONE_DIMENSION, *SEVERAL, Point("plcName", "STRING")]


def held(sim: TecomatSimulator, point: Point) -> Any:
    """Return what the simulator holds at a point, as the client shows it."""
    value = sim.get(point.address.replace(" ", ""))
    return pytest.approx(value, rel=1e-6) if point.data_type == "REAL" else value


@pytest.mark.parametrize("fits", [True, False], ids=["whole", "too-big"])
@pytest.mark.parametrize("shape", ARRAY_ANSWERS)
async def test_several_elements_in_one_poll(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient, shape: str, fits: bool
) -> None:
    """2-D, 3-level and 1-D elements in one poll: each shows its own value, or fails.

    An array that fits one answer is read whole, as 5.2 shows it: every element is right
    whatever shape the PLC gives elements. One too big (413.004) has its elements asked; a list
    longer than asked (`whole`, `partial`) is placed by position once a probe of its corners
    confirmed the array starts at 0; only a flat list of the asked leaves cannot say where a
    multi-dimensional element goes: it fails. Before, arr2[1][1] showed arr2[1][3]'s value when
    the PLC answered nested, partial arrays; then whole and partial lists failed every element.
    """
    tecomat_sim.array_answers = shape
    if not fits:
        tecomat_sim.max_variables = 10  # arr2 holds 12 items, arr3 24: neither answers whole
    for _ in range(2):  # the second poll asks the elements of too big arrays straight away
        result = await tecomat_client.read(POINTS)
        for point in POINTS:
            outcome = result.values[point]
            if outcome.ok:
                assert outcome.value == held(tecomat_sim, point), point.address
            else:  # a flat list of N-D leaves: no known index
                assert (fits, shape, point in SEVERAL) == (False, "flat", True), point.address
    if fits:  # the first poll confirmed each array starts at 0 (READINGS.md row 18)
        assert tecomat_client.metrics.last_poll_requests == 1
        assert {"arr2", "arr3"} <= set(tecomat_sim.uris[-1].partition("?")[2].split("&"))


@pytest.mark.parametrize("spelling", ELEMENT_SPELLINGS)
async def test_element_spelling_of_an_array_too_big(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient, spelling: str
) -> None:
    """Asked element by element, arr2[1][3] is sent so; a PLC taking only arr2[1,3] fails it."""
    tecomat_sim.element_spelling = spelling
    tecomat_sim.max_variables = 10
    result = await tecomat_client.read(POINTS)
    for point in POINTS:
        outcome = result.values[point]
        if outcome.ok:
            assert outcome.value == held(tecomat_sim, point), point.address
        else:
            assert (spelling, point in SEVERAL) == ("comma", True), point.address
            assert isinstance(outcome.error, PlcAddressError)


async def test_an_element_beyond_the_array_fails_alone(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    """arr1 holds 6 elements: arr1[9] fails, arr1[0] read with it is right."""
    first, beyond = Point("arr1[0]", "STRING"), Point("arr1[9]", "STRING")
    result = await tecomat_client.read([first, beyond])
    assert result.values[first].value == "zero"
    assert isinstance(result.values[beyond].error, PlcAddressError)  # a repair issue names it
    assert "arr1 has no such element" in str(result.values[beyond].error)


async def test_array_grown_too_big_is_read_by_elements(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    """413.004 for the whole array: its elements are asked, the same poll and the next ones."""
    tecomat_sim.variables["big"] = [Var("INT", index) for index in range(200)]
    points = [Point(f"big[{index}]", "INT") for index in (3, 150, 199)]
    first = await tecomat_client.read(points)
    assert [first.values[point].value for point in points] == [3, 150, 199]
    assert tecomat_client.metrics.last_poll_requests == 2  # the whole, then the elements
    await tecomat_client.read(points)
    assert tecomat_client.metrics.last_poll_requests == 1
    assert tecomat_sim.uris[-1].endswith("?big[3]&big[150]&big[199]")  # in index order


@pytest.mark.parametrize("lows", [None, (0, 0)], ids=["first-index-unknown", "from-0"])
@pytest.mark.parametrize(
    ("answer", "value", "from_zero"),
    [
        ({"arr2": [[1.1, 1.3]]}, None, None),  # compact: one row asked, two columns: by order
        ({"arr2": [None, [0, 1.1, 0, 1.3]]}, "absent", 1.1),  # padded from the first index
        ({"arr2": {"1": {"1": 1.1, "3": 1.3}}}, 1.1, 1.1),
        ({"arr2[1][1]": 1.1, "arr2[1][3]": 1.3}, 1.1, 1.1),
        ({"ARR2[1,1]": 1.1, "arr2[1, 3]": 1.3}, 1.1, 1.1),
        ({"arr2[1]": [0, 1.1, 0, 1.3]}, "absent", 1.1),  # a row by position from its first
        ({"arr2": [1.1, 1.3]}, "absent", "absent"),  # flat: a number cannot be indexed again
        ({"arr2": [[1.1, 1.3, 5.0]]}, "absent", "absent"),  # compact, then longer: no shape
        ({"arr2": [[1.1]]}, "absent", "absent"),
    ],
)
def test_answer_shapes(
    answer: Any, value: Any, from_zero: Any, lows: tuple[int, ...] | None
) -> None:
    """arr2[1][1] and arr2[1][3]: placed only where the shape names the index.

    A list longer than asked holds elements by position from the array's first index: placed
    once it is known (here 0, as a probe or GetList gives it), never before.
    """
    paths = [parse_path("arr2[1][1]"), parse_path("arr2[1][3]")]
    found = answered(answer, paths, None if lows is None else {"arr2": lows})
    expected = value if lows is None else from_zero
    if expected == "absent":
        assert found == {}
    elif expected is None:
        assert found == {"arr2[1][1]": 1.1, "arr2[1][3]": 1.3}
    else:
        assert found["arr2[1][1]"] == expected
        assert found["arr2[1][3]"] == 1.3


def test_lists_placed_from_a_first_index_not_0() -> None:
    """ARRAY[1..5] asked for [2] and [4]: a padded or whole list placed from 1 once known."""
    paths = [parse_path("arrB[2]"), parse_path("arrB[4]")]
    for answer in ([None, 20, None, 40], [10, 20, 30, 40, 50]):
        assert answered({"arrB": answer}, paths) == {}
        assert answered({"arrB": answer}, paths, {"arrb": (1,)}) == {
            "arrb[2]": 20,
            "arrb[4]": 40,
        }
    assert answered({"arrB": [20, 40]}, paths, {"arrb": (1,)}) == {"arrb[2]": 20, "arrb[4]": 40}


def test_a_list_of_no_known_shape_places_nobody() -> None:
    """Three items for two asked indices beyond its length: neither shape, so no value at all."""
    paths = [parse_path("arr1[5]"), parse_path("arr1[7]")]
    assert answered({"arr1": ["a", "b", "c"]}, paths) == {}
    assert answered({"arr1": ["a", "b"]}, paths) == {"arr1[5]": "a", "arr1[7]": "b"}
    full = [str(index) for index in range(8)]  # the whole array, from an index it does not say
    assert answered({"arr1": full}, paths) == {}
