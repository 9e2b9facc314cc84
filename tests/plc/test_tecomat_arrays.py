"""Array elements in every answer shape: never a value under another point's index (issue 10)."""

from __future__ import annotations

import pytest

from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient
from custom_components.plc_bridge.plc.vendors.tecomat.paths import answered, parse_path
from simulators.tecomat import TecomatSimulator


@pytest.mark.parametrize("compact", [False, True], ids=["keyed", "compact"])
async def test_elements_read_right_in_both_shapes(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient, compact: bool
) -> None:
    """arr1[1] and arr1[4]: answered keyed or as a shorter array, each shows its own element."""
    tecomat_sim.compact_arrays = compact
    one, four = Point("arr1[1]", "STRING"), Point("arr1[4]", "STRING")
    result = await tecomat_client.read([one, four])
    assert result.values[one].value == tecomat_sim.get("arr1[1]")
    assert result.values[four].value == tecomat_sim.get("arr1[4]")
    assert result.values[one].value != result.values[four].value


def test_a_list_of_no_known_shape_places_nobody() -> None:
    """Three items for two asked indices beyond its length: neither shape, so no value at all."""
    paths = [parse_path("arr1[5]"), parse_path("arr1[7]")]
    assert answered({"arr1": ["a", "b", "c"]}, paths) == {}
    assert answered({"arr1": ["a", "b"]}, paths) == {"arr1[5]": "a", "arr1[7]": "b"}
    full = [str(index) for index in range(8)]
    assert answered({"arr1": full}, paths) == {"arr1[5]": "5", "arr1[7]": "7"}
