"""The Tecomat client when the PLC answers oddly: bad JSON, Windows-1250, refusals, listings."""

from __future__ import annotations

import pytest

from custom_components.plc_bridge.plc import PlcProtocolError, Point
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient
from simulators.tecomat import TecomatSimulator
from simulators.tecomat.values import Var


async def test_odd_answers(tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient) -> None:
    point = Point("plcDesc", "STRING")
    tecomat_sim.rewrite = lambda body: body.replace(b"for testing only", "°C".encode("cp1250"))
    assert (await tecomat_client.read([point])).values[point].value == "°C"
    tecomat_sim.rewrite = lambda body: b"{}"
    error = (await tecomat_client.read([point])).values[point].error
    assert "missing from the answer" in str(error)
    tecomat_sim.rewrite = lambda body: body.replace(b'"time":"', b'"time":"at ')
    with pytest.raises(PlcProtocolError, match="holds no valid time"):
        await tecomat_client.read_clock()
    tecomat_sim.rewrite = lambda body: b"<html>"
    with pytest.raises(PlcProtocolError, match="other than JSON"):
        await tecomat_client.read([point])


async def test_write_refused_as_a_whole(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    tecomat_sim.max_variables = 1
    with pytest.raises(PlcProtocolError, match=r"Too many variables \(maximum is 1\) \(413.004\)"):
        await tecomat_client.write(
            {Point("plcName", "STRING"): "a", Point("plcDesc", "STRING"): "b"}
        )
    assert tecomat_client.metrics.errors == 1


async def test_browse_odd_listing(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    tecomat_sim.variables = {"plcName": tecomat_sim.variables["plcName"], "1bad": Var("INT", 1)}
    assert [item.address for item in await tecomat_client.browse()] == ["plcName"]


@pytest.mark.parametrize("asked_case", [False, True], ids=["declared", "asked"])
async def test_names_in_any_case(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient, asked_case: bool
) -> None:
    """Names are case-insensitive (3.4, 3.5, 4); the answer may spell them either way."""
    tecomat_sim.asked_case = asked_case
    points = {
        Point("MYOBJECT.favorites.SPORT", "STRING"): "Soccer",
        Point("myobject.First", "STRING"): "John",
        Point("ARR2[1][3]", "REAL"): 1.3,
        Point("arr2[2][0]", "REAL"): 2.0,
        Point("PLCNAME", "STRING"): "myFoxtrot",
    }
    result = await tecomat_client.read(list(points))
    assert {point: result.values[point].value for point in points} == points
