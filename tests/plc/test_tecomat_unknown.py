"""Variables the PLC does not know or refuses, named by path or by their last item only."""

from __future__ import annotations

import time

import pytest

from custom_components.plc_bridge.plc import PlcAddressError, PlcValueError, Point
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient, client as client_module
from simulators.tecomat import TecomatSimulator

SPORT, COLOR = (
    Point("myObject.favorites.sport", "STRING"),
    Point("myObject.favorites.color", "STRING"),
)
NAME, REQUESTED = Point("plcName", "STRING"), Point("Main.myObject3.value", "REAL")
PUMP = Point("Main.pump.value", "BOOL")


def later(monkeypatch: pytest.MonkeyPatch, seconds: float) -> None:
    """Let the client's clock run `seconds` past the real one."""
    monkeypatch.setattr(client_module, "monotonic", lambda: time.monotonic() + seconds)


async def test_unknown_variable_named_by_its_last_item(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    tecomat_sim.leaf_names = True
    tecomat_sim.rename("myObject.favorites.sport", "hobby")
    before = tecomat_sim.calls["GetObject"]
    result = await tecomat_client.read([SPORT, COLOR, NAME, REQUESTED])
    assert tecomat_sim.calls["GetObject"] - before == 2  # the answer names "sport": only it goes
    error = result.values[SPORT].error
    assert isinstance(error, PlcAddressError)
    assert str(error) == (
        "myObject.favorites.sport: the PLC does not know this variable "
        "(400.005: 'sport' is not found)"
    )
    assert [result.values[p].value for p in (COLOR, NAME, REQUESTED)] == ['"Blue"', "myFoxtrot", 23]


async def test_unknown_structure_member(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    tecomat_sim.leaf_names = True
    tecomat_sim.rename("myObject.favorites", "likes")
    before = tecomat_sim.calls["GetObject"]
    result = await tecomat_client.read([SPORT, COLOR, NAME])
    assert tecomat_sim.calls["GetObject"] - before == 2  # 'favorites' holds both: both go at once
    assert "'favorites' is not found" in str(result.values[SPORT].error)
    assert isinstance(result.values[COLOR].error, PlcAddressError)
    assert result.values[NAME].value == "myFoxtrot"


async def test_unknown_variable_the_answer_does_not_single_out(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    tecomat_sim.leaf_names = True
    tecomat_sim.rename("Main.pump.value", "state")  # 'value' fits both Main objects
    before = tecomat_sim.calls["GetObject"]
    result = await tecomat_client.read([REQUESTED, PUMP, NAME])
    assert tecomat_sim.calls["GetObject"] - before == 4  # halves: one reads, one drops the pump
    assert isinstance(result.values[PUMP].error, PlcAddressError)
    assert (result.values[REQUESTED].value, result.values[NAME].value) == (23, "myFoxtrot")


async def test_write_refusal_naming_the_leaf(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    tecomat_sim.leaf_names = True
    age, food = Point("myObject.age", "INT"), Point("myObject.favorites.food", "STRING")
    missing = Point("myObject.favorites.drink", "STRING")
    results = await tecomat_client.write({SPORT: "Chess", age: 300, food: "Pizza", missing: "Tea"})
    assert str(results[age].error) == (
        "myObject.age: the PLC did not take 300 (the variable is a USINT; 400.015)"
    )
    assert "'drink' is not found" in str(results[missing].error)
    assert results[SPORT].ok
    assert results[food].ok
    assert (tecomat_sim.get("myObject.favorites.sport"), tecomat_sim.get("myObject.age")) == (
        "Chess",
        39,
    )
    assert tecomat_sim.get("myObject.favorites.food") == "Pizza"
    assert tecomat_sim.calls["PutObject"] == 3


async def test_write_refusal_the_answer_does_not_single_out(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    tecomat_sim.leaf_names = True
    pump = Point("Main.pump.value", "INT")  # the PLC's BOOL refuses 5, naming only 'value'
    results = await tecomat_client.write({pump: 5, REQUESTED: 21.5, NAME: "x"})
    error = results[pump].error
    assert isinstance(error, PlcValueError)
    assert "400.015" in str(error)
    assert results[REQUESTED].ok
    assert results[NAME].ok
    assert (tecomat_sim.get("Main.myObject3.value"), tecomat_sim.get("plcName")) == (21.5, "x")
    assert tecomat_sim.calls["PutObject"] == 3  # all, then each half


@pytest.mark.parametrize("stamps", [True, False], ids=["new-stamp", "same-stamp"])
async def test_unknown_variable_costs_no_request_per_poll(
    tecomat_sim: TecomatSimulator,
    tecomat_client: TecomatClient,
    monkeypatch: pytest.MonkeyPatch,
    stamps: bool,
) -> None:
    """Not asked at every poll; asked again at a new program stamp, or on its own timer."""
    tecomat_sim.rename_stamps = stamps
    good = [NAME, Point("plcDesc", "STRING"), REQUESTED]
    lost = Point("plcType", "UINT")
    await tecomat_client.read(good)
    usual = tecomat_client.metrics.last_poll_requests
    tecomat_sim.rename("plcType", "plcKind")
    await tecomat_client.read([*good, lost])
    # found out once, and the program stamp read as it went (a rename back then shows)
    assert tecomat_client.metrics.last_poll_requests == usual + 2
    tecomat_sim.rename("plcKind", "plcType")  # the PLC program is fixed
    for _ in range(3):
        result = await tecomat_client.read([*good, lost])
        assert tecomat_client.metrics.last_poll_requests == usual
        assert isinstance(result.values[lost].error, PlcAddressError)
        assert result.values[NAME].value == "myFoxtrot"
    assert all("plcType" not in uri for uri in list(tecomat_sim.uris)[-3:])
    later(monkeypatch, 61)  # GetInfo (its stamp) and the variable's first timer are due
    getting = tecomat_sim.calls["GetObject"]
    result = await tecomat_client.read([*good, lost])
    # A new stamp puts it back in the plan; else it is asked again on its own, then read.
    assert tecomat_sim.calls["GetObject"] - getting == usual + (0 if stamps else 1)
    assert result.values[lost].value == 2005
    getting = tecomat_sim.calls["GetObject"]
    await tecomat_client.read([*good, lost])
    assert tecomat_sim.calls["GetObject"] - getting == usual  # back in the plan


async def test_renamed_structure_found_in_few_requests(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    """A PLC that names whole paths: a renamed structure costs a probe, not a request per member."""
    members = ["varBool1", "varInt", "varReal", "varString", "varDT", "varTime", "varDint"]
    points = [Point(f"plcData.{member}", "INT") for member in members]
    tecomat_sim.rename("plcData", "plcData2")
    before = tecomat_sim.calls["GetObject"]
    result = await tecomat_client.read([*points, NAME])
    assert tecomat_sim.calls["GetObject"] - before == 3  # refused, the probe of plcData, the rest
    assert all(isinstance(result.values[point].error, PlcAddressError) for point in points)
    assert result.values[NAME].value == "myFoxtrot"


async def test_fewer_names_learned(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    """A CPU taking 3 names a request (413.002): halved while refused, then kept as learned."""
    tecomat_sim.max_variables = 3
    members = ["varBool1", "varInt", "varReal", "varString", "varDT", "varTime", "varDint"]
    points = [Point(f"plcData.{member}", "INT") for member in members]
    first = await tecomat_client.read(points)
    assert not [p for p, r in first.values.items() if isinstance(r.error, PlcValueError)]
    before = tecomat_sim.calls["GetObject"]
    await tecomat_client.read(points)
    assert tecomat_sim.calls["GetObject"] - before == 4  # halved to 3, then 2 names a request
