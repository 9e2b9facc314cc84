"""Refusals worded unlike the manual (localised, newer firmware): narrowed down by their code.

3.7 words 400.005 "Variable 'NNN' is not found"; a PLC may word it otherwise
(simulators/tecomat/READINGS.md, "error texts"). Before, a text the client could not parse failed
every point of the poll, at every poll (issue 23).
"""

from __future__ import annotations

import pytest

from custom_components.plc_bridge.plc import PlcAddressError, PlcValueError, Point
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient
from simulators.tecomat import TecomatSimulator
from simulators.tecomat.values import ERROR_TEXTS

NAME, KIND = Point("plcName", "STRING"), Point("plcType", "UINT")
SPORT = Point("myObject.favorites.sport", "STRING")
GONE = Point("plcKind", "UINT")
POINTS = [NAME, KIND, SPORT, GONE, Point("arr1[2]", "STRING"), Point("Main.pump.value", "BOOL")]


@pytest.mark.parametrize("leaf_names", [False, True], ids=["whole-path", "stopping-item"])
@pytest.mark.parametrize("texts", ERROR_TEXTS)
async def test_only_the_unknown_variable_fails(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient, texts: str, leaf_names: bool
) -> None:
    """One unknown variable among six: it fails alone, whatever the 400.005 text says."""
    tecomat_sim.error_texts, tecomat_sim.leaf_names = texts, leaf_names
    tecomat_sim.rename("myObject.favorites", "likes")
    for _ in range(2):  # the second poll skips what the first found unknown
        result = await tecomat_client.read(POINTS)
        failed = {point for point, outcome in result.values.items() if not outcome.ok}
        assert failed == {SPORT, GONE}
        assert all(isinstance(result.values[point].error, PlcAddressError) for point in failed)
        assert result.values[KIND].value == 2005
        assert result.values[NAME].value == "myFoxtrot"
        assert result.values[POINTS[4]].value == "two"


@pytest.mark.parametrize("texts", ERROR_TEXTS)
async def test_only_the_refused_writes_fail(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient, texts: str
) -> None:
    """An unknown variable and a value out of range fail alone; the others are written."""
    tecomat_sim.error_texts = texts
    age, food = Point("myObject.age", "INT"), Point("myObject.favorites.food", "STRING")
    results = await tecomat_client.write({SPORT: "Chess", age: 300, food: "Pizza", GONE: 7})
    assert isinstance(results[age].error, PlcValueError)
    assert isinstance(results[GONE].error, PlcAddressError)
    assert results[SPORT].ok
    assert results[food].ok
    assert tecomat_sim.get("myObject.favorites.food") == "Pizza"
    assert tecomat_sim.get("myObject.age") == 39
