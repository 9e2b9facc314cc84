"""PLCnext browsing against the simulator: array bounds, arrays in structures, member types."""

from __future__ import annotations

from typing import Any

import pytest

from custom_components.plc_bridge.plc import BrowseItem, Point
from custom_components.plc_bridge.plc.vendors.plcnext import PlcnextClient
from custom_components.plc_bridge.plc.vendors.plcnext.browse import Declared, bounds, leaves
from custom_components.plc_bridge.plc.vendors.plcnext.paths import parse_path
from simulators.plcnext import PlcnextSimulator

MAIN = "Arp.Plc.Eclr/MainInstance."


def by_address(items: list[BrowseItem]) -> dict[str, BrowseItem]:
    """Return browse items by address."""
    return {item.address: item for item in items}


async def test_array_bounds_from_dimension_objects(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient
) -> None:
    """`"Dimensions": [{"StartIndex": 1, "Length": 4}]`: elements 1..4, never 0.

    Before: the bounds were looked for as a `"[1..4]"` text, so [0..3] was offered.
    """
    (levels,) = (
        entry
        for entry in plcnext_sim.program.type_dictionary()["Types"]
        if entry["Name"] == "LevelArray"
    )
    assert levels["Dimensions"] == [{"StartIndex": 1, "Length": 4}]
    items = by_address(await plcnext_client.browse())
    offered = sorted(address for address in items if address.startswith(MAIN + "Levels"))
    assert offered == [f"{MAIN}Levels[{index}]" for index in (1, 2, 3, 4)]
    assert items[MAIN + "Levels[1]"].data_type == "INT"
    assert not items[MAIN + "Levels[1]"].guessed
    read = await plcnext_client.read([Point(a, "INT") for a in offered], poll=False)
    assert [result.value for result in read.values.values()] == [10, 20, 30, 40]


async def test_arrays_in_structures_and_arrays_of_arrays(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient
) -> None:
    """A structure's array member takes its bounds from the type a register answer names;
    an array of arrays takes its element type's bounds; the group asked is unregistered.

    Before: an array inside a structure was numbered from 0 (`Steps[0]` does not exist).
    """
    items = by_address(await plcnext_client.browse())
    steps = sorted(address for address in items if ".Recipe.Steps" in address)
    assert steps == [f"{MAIN}Recipe.Steps[{index}]" for index in (1, 2, 3)]
    assert items[MAIN + "Recipe.Steps[1]"].data_type == "DINT"
    assert items[MAIN + "Recipe.Weight"].data_type == "REAL"  # declared, not guessed from JSON
    assert not items[MAIN + "Recipe.Weight"].guessed
    shifts = sorted(address for address in items if address.startswith(MAIN + "Shifts"))
    assert shifts == [f"{MAIN}Shifts[{day}][{n}]" for day in (5, 6, 7) for n in (0, 1)]
    assert items[MAIN + "Shifts[6][1]"].data_type == "UINT"
    assert not plcnext_sim.groups
    points = [Point(address, items[address].data_type) for address in (*steps, *shifts)]
    read = await plcnext_client.read(points, poll=False)
    assert all(result.ok for result in read.values.values())


async def test_multi_dimensional_arrays_offer_no_element(
    plcnext_client: PlcnextClient,
) -> None:
    """No source shows an element path of ARRAY[0..1, 1..2]: none is offered (never a guess)."""
    items = by_address(await plcnext_client.browse())
    assert not [address for address in items if address.startswith(MAIN + "Grid")]


async def test_member_types_unknown_without_groups(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient
) -> None:
    """Where groups are not served, a structure's scalars are guessed and its arrays left out."""
    plcnext_sim.groups_served = False
    items = by_address(await plcnext_client.browse())
    assert items[MAIN + "Recipe.Weight"].guessed
    assert not [address for address in items if ".Recipe.Steps" in address]
    assert MAIN + "Levels[4]" in items  # a declared array keeps its bounds


@pytest.mark.parametrize(
    "dimensions",
    [
        "[1..4]",  # a text form no source shows
        None,
        [],
        [{"StartIndex": "1", "Length": 4}],
        [{"StartIndex": 1, "Length": True}],
        [{"StartIndex": 1, "Length": 5}],  # disagrees with the value
        [{"Start": 1, "Length": 4}],
    ],
)
def test_unreadable_bounds_offer_no_element(dimensions: Any) -> None:
    """Bounds the client cannot read, or that disagree with the value: no element offered."""
    known = {"LEVELARRAY": {"Name": "LevelArray", "ElementType": "INT", "Dimensions": dimensions}}
    variable = Declared(parse_path("Main.Levels"), "LevelArray", False)
    assert not list(leaves(variable, [10, 20, 30, 40], known))


def test_bounds() -> None:
    """One (first index, length) per dimension."""
    about = {"Dimensions": [{"StartIndex": -2, "Length": 3}, {"StartIndex": 0, "Length": 2}]}
    assert bounds(about) == ((-2, 3), (0, 2))
    assert bounds({"Dimensions": [{"StartIndex": 0, "Length": -1}]}) is None


def test_deeply_nested_values_do_not_recurse_without_end() -> None:
    """A value nested deeper than any PLC type ends in no item, not a RecursionError."""
    value: Any = 1
    for _ in range(5000):
        value = {"a": value}
    variable = Declared(parse_path("Main.Deep"), "DeepType", False)
    assert not list(leaves(variable, value, {}))
