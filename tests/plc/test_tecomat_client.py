"""The Tecomat client against the TecoApi simulator: reads, writes, types, browse, clock."""

from __future__ import annotations

from datetime import date, datetime, timedelta
import math
from typing import TYPE_CHECKING
from zoneinfo import ZoneInfo

import pytest

from custom_components.plc_bridge.plc import (
    DeviceInfo,
    PlcAddressError,
    PlcProtocolError,
    PlcValueError,
    PlcWriteRefusedError,
    Point,
    Value,
)
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient, client as client_module
from custom_components.plc_bridge.plc.vendors.tecomat.paths import VariablePath, parse_path
from simulators.tecomat import TecomatSimulator

if TYPE_CHECKING:
    from .tecomat_fixtures import ConfigFactory


PRAGUE = ZoneInfo("Europe/Prague")
ROUND_TRIPS: list[tuple[str, str, Value]] = [
    ("plcData.varBool0", "BOOL", True),
    ("plcData.varByte", "BYTE", 255),
    ("plcData.varWord", "WORD", 65535),
    ("plcData.varDword", "DWORD", 2**32 - 1),
    ("plcData.varUsint", "USINT", 200),
    ("plcData.varUint", "UINT", 60000),
    ("plcData.varUdint", "UDINT", 4_000_000_000),
    ("plcData.varSint", "SINT", -128),
    ("plcData.varInt", "INT", -32768),
    ("plcData.varDint", "DINT", -(2**31)),
    ("plcData.varReal", "REAL", -1.25),
    ("plcData.varLreal", "LREAL", 123456.5),
    ("plcData.varTime", "TIME", timedelta(milliseconds=2**31 - 1)),
    ("plcData.varTod", "TOD", timedelta(milliseconds=86_399_999)),
    ("plcData.varDate", "DATE", datetime(2024, 2, 29, tzinfo=PRAGUE)),
    ("plcData.varDT", "DT", datetime(2025, 7, 1, 12, 30, 15, 250000, tzinfo=PRAGUE)),
    ("plcData.varString", "STRING", 'say "hi" \\ ok'),
    ("plcData.varStringArray[5]", "STRING", "FIVE"),
    ("arr3[1][2][3]", "BYTE", 7),
    ("myObject.interests[1]", "STRING", "Cooking"),
]


async def test_device_info(tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient) -> None:
    assert await tecomat_client.connect() == DeviceInfo(
        vendor="tecomat",
        model="Fx2 CP2080",
        serial="PP 0004",
        mac="F8-DC-7A-11-F4-DC",
        firmware="Fx2 CP2080I v1.1",
        extra={
            "api": "TecoApi v1.0.0",
            "family": "Fx2",
            "cpu": "CP2080",
            "program": "DOC_TECOAPI v1.0",
        },
    )
    result = await tecomat_client.read([])
    assert result.status.mode == "RUN"
    assert result.status.clock == datetime(2018, 1, 31, 16, 50, 39, 949000, tzinfo=PRAGUE)
    assert result.status.extra == {
        "program": "DOC_TECOAPI v1.0",
        "program_compiled": "2018-01-18T16:39:38+01:00",  # PLC digits, in its zone
        "program_stamp": "E28AE29B",
    }
    assert tecomat_sim.calls == {"GetInfo": 2}


@pytest.mark.parametrize(("mode", "shown"), [("HALT", "HALT"), ("ERR", "ERROR"), ("RUN", "RUN")])
async def test_status_cadence(
    tecomat_sim: TecomatSimulator,
    tecomat_client: TecomatClient,
    monkeypatch: pytest.MonkeyPatch,
    mode: str,
    shown: str,
) -> None:
    tecomat_sim.mode = mode
    point = Point("plcName", "STRING")
    assert (await tecomat_client.read([point])).status.mode == "RUN"  # GetInfo not due yet
    assert tecomat_sim.calls["GetInfo"] == 1
    monkeypatch.setattr(TecomatClient, "status_interval", 0.0)
    assert (await tecomat_client.read([point])).status.mode == shown
    assert tecomat_sim.calls["GetInfo"] == 2


async def test_every_type_round_trip(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    values = {Point(address, kind): value for address, kind, value in ROUND_TRIPS}
    written = await tecomat_client.write(values)
    assert all(result.ok for result in written.values())
    assert tecomat_sim.calls["PutObject"] == 1
    before = tecomat_sim.requests
    result = await tecomat_client.read(list(values))
    assert {point: outcome.value for point, outcome in result.values.items()} == values
    # GetList (no declared bounds) and one request confirm arr3 starts at 0, once a program
    # (READINGS.md row 18)
    assert tecomat_sim.requests - before == TecomatClient.requests_for(list(values)) + 2 == 4
    before = tecomat_sim.requests
    await tecomat_client.read(list(values))
    assert tecomat_sim.requests - before == 2
    assert tecomat_sim.get("plcData.varTime") == 2**31 - 1
    assert tecomat_sim.get("plcData.varDate") == date(2024, 2, 29)
    assert tecomat_sim.get("plcData.varDT") == datetime(2025, 7, 1, 12, 30, 15, 250000)
    assert tecomat_sim.get("arr1[5]") == ""


async def test_dt_in_the_plc_zone(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    point = Point("plcData.varDT", "DT")
    await tecomat_client.write({point: datetime(2025, 1, 1, 11, 0, tzinfo=ZoneInfo("UTC"))})
    assert tecomat_sim.get("plcData.varDT") == datetime(2025, 1, 1, 12, 0)
    await tecomat_client.write({point: "2025-03-04T05:06:07"})
    value = (await tecomat_client.read([point])).values[point].value
    assert value == datetime(2025, 3, 4, 5, 6, 7, tzinfo=PRAGUE)


async def test_poll_of_200_points_at_the_uri_bound(tecomat_config: ConfigFactory) -> None:
    sim = TecomatSimulator(bench=300)
    await sim.start()
    client = TecomatClient(tecomat_config(port=sim.port))
    try:
        await client.connect()
        leaves = [Point(item.address, item.data_type) for item in await client.browse()]
        points = leaves + [Point(f"BENCH.V{i}", "INT") for i in range(200 - len(leaves))]
        assert len(points) == 200
        before = sim.requests
        result = await client.read(points)
        assert all(outcome.ok for outcome in result.values.values())
        names = sum(len(point.address) + 1 for point in points)
        bound = TecomatClient.requests_for(points)  # arrays read whole (5.2) need fewer
        assert bound < math.ceil(names / (256 - len("/TecoApi/GetObject?") + 1))
        assert sim.requests - before == client.metrics.last_poll_requests == bound
        assert max(len(uri) for uri in list(sim.uris)[-bound:]) <= 256
        await client.read(points)  # the plan is kept between polls
        assert sim.requests - before == 2 * bound
    finally:
        await client.close()
        await sim.stop()


async def test_renamed_variable(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    points = [
        Point("plcName", "STRING"),
        Point("plcType", "UINT"),
        Point("myObject.favorites.sport", "STRING"),
        Point("plcDesc", "STRING"),
    ]
    tecomat_sim.rename("plcType", "plcKind")
    tecomat_sim.rename("myObject.favorites.sport", "hobby")
    before = tecomat_sim.calls["GetObject"]
    result = await tecomat_client.read(points)
    assert tecomat_sim.calls["GetObject"] - before == 3  # one unknown a request, then the rest
    assert result.values[points[0]].value == "myFoxtrot"
    assert result.values[points[3]].value == "for testing only"
    for lost in (points[1], points[2]):
        error = result.values[lost].error
        assert isinstance(error, PlcAddressError)
        assert lost.address in str(error)
    assert (await tecomat_client.read([Point("plckind", "UINT")])).values[
        Point("plckind", "UINT")
    ].value == 2005


async def test_names_are_case_insensitive(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    upper, lower = Point("MYOBJECT.FAVORITES.SPORT", "STRING"), Point("myobject.first", "string")
    same = Point("myObject.favorites.sport", "STRING")
    before = tecomat_sim.requests
    result = await tecomat_client.read([upper, lower, same])
    assert tecomat_sim.requests - before == 1
    assert tecomat_sim.uris[-1] == "/TecoApi/GetObject?MYOBJECT.FAVORITES.SPORT&myobject.first"
    assert [result.values[p].value for p in (upper, lower, same)] == ["Soccer", "John", "Soccer"]
    written = await tecomat_client.write(
        {Point("PLCDESC", "STRING"): "x", Point("MyObject.Age", "USINT"): 41}
    )
    assert all(outcome.ok for outcome in written.values())
    assert tecomat_sim.get("plcDesc") == "x"
    assert tecomat_sim.get("myObject.age") == 41


async def test_floats_written_plain(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    real, lreal = Point("plcData.varReal", "REAL"), Point("plcData.varLreal", "LREAL")
    assert [str(value) for value in (1e-05, 1.5e-7, 1e20)] == ["1e-05", "1.5e-07", "1e+20"]
    await tecomat_client.write({real: 1e-05, lreal: 1.5e-7})
    await tecomat_client.write({lreal: 1e20})
    assert list(tecomat_sim.bodies) == [
        b'{"plcData":{"varReal":0.00001,"varLreal":0.00000015}}',
        b'{"plcData":{"varLreal":100000000000000000000}}',
    ]
    assert (await tecomat_client.read([real])).values[real].value == pytest.approx(1e-05)


async def test_non_ascii_refused_before_sending(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    before = tecomat_sim.requests
    with pytest.raises(PlcValueError, match="ASCII text only; 'Ž' is not ASCII"):
        await tecomat_client.write({Point("plcDesc", "STRING"): "Žluťoučký kůň"})
    assert tecomat_sim.requests == before
    assert tecomat_sim.get("plcDesc") == "for testing only"


async def test_value_refused_by_the_plc(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    age, name = Point("myObject.age", "INT"), Point("myObject.first", "STRING")
    missing = Point("myObject.middle", "STRING")
    results = await tecomat_client.write({age: 300, name: "Mia", missing: "Q"})
    error = results[age].error
    assert isinstance(error, PlcValueError)
    assert str(error) == "myObject.age: the PLC did not take 300 (the variable is a USINT; 400.015)"
    assert isinstance(results[missing].error, PlcAddressError)
    assert "myObject.middle" in str(results[missing].error)
    assert results[name].value == "Mia"
    assert tecomat_sim.get("myObject.first") == "Mia"
    assert tecomat_sim.get("myObject.age") == 39
    assert tecomat_sim.calls["PutObject"] == 3


async def test_struct_point_and_bad_points(tecomat_client: TecomatClient) -> None:
    struct, bad = Point("myObject.favorites", "STRING"), Point("1abc", "INT")
    untyped, wrong = Point("plcName", "FLOAT"), Point("plcName", "INT")
    result = await tecomat_client.read([struct, bad, untyped, wrong])
    assert "is a structure" in str(result.values[struct].error)
    assert isinstance(result.values[bad].error, PlcAddressError)
    assert isinstance(result.values[untyped].error, PlcAddressError)
    assert isinstance(result.values[wrong].error, PlcProtocolError)
    assert TecomatClient.requests_for([bad, untyped]) == 0


async def test_browse(tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient) -> None:
    items = {item.address: item for item in await tecomat_client.browse()}
    assert items["myObject.favorites.sport"].data_type == "STRING"
    assert items["myObject.interests[2]"].data_type == "STRING"
    assert items["arr2[1][3]"].data_type == "REAL"
    assert items["arr3[1][2][3]"].data_type == "DINT"
    assert items["plcData.varBool1"].data_type == "BOOL"
    assert items["plcData.varDT"].data_type == "DT"
    assert items["plcData.varDate"].data_type == "DATE"
    assert items["plcData.varTime"].data_type == "TIME"
    inside, requested = items["Main.myObject2.value"], items["Main.myObject3.value"]
    assert (inside.name, inside.unit, inside.read_only, inside.platform) == (
        "inside temperature",
        "°C",
        True,
        "sensor",
    )
    assert (inside.minimum, inside.maximum) == (None, None)
    assert (requested.minimum, requested.maximum, requested.platform) == (10.0, 30.0, "number")
    assert items["Main.pump.value"].platform == "switch"
    assert not any(".attr." in address for address in items)
    for item in items.values():
        assert (
            TecomatClient.validate_point(Point(item.address, item.data_type)).address
            == item.address
        )


async def test_browse_reports_a_structure_too_big_to_read(tecomat_config: ConfigFactory) -> None:
    """BENCH (129 INTs) cannot be read at once, nor its members named: listed as unlisted."""
    sim = TecomatSimulator(bench=129)
    await sim.start()
    client = TecomatClient(tecomat_config(port=sim.port))
    try:
        items = await client.browse()
        assert not any(item.address.startswith("BENCH") for item in items)
        assert "plcName" in {item.address for item in items}
        assert client.unlisted == ["BENCH"]
    finally:
        await client.close()
        await sim.stop()


async def test_clock(
    tecomat_sim: TecomatSimulator, tecomat_config: ConfigFactory, tecomat_client: TecomatClient
) -> None:
    assert await tecomat_client.read_clock() == datetime(
        2018, 1, 31, 16, 50, 39, 949000, tzinfo=PRAGUE
    )
    with pytest.raises(PlcWriteRefusedError, match="choose a DT variable that the PLC program"):
        await tecomat_client.set_clock(datetime(2026, 1, 2, 3, 4, 5, tzinfo=PRAGUE))
    assert not tecomat_client.can_set_clock
    client = TecomatClient(tecomat_config(options={"clock_variable": "setTime"}))
    assert client.can_set_clock
    await client.set_clock(datetime(2026, 1, 2, 3, 4, 5, tzinfo=PRAGUE))
    assert tecomat_sim.clock == datetime(2026, 1, 2, 3, 4, 5)
    assert await client.read_clock() == datetime(2026, 1, 2, 3, 4, 5, tzinfo=PRAGUE)
    bad = TecomatClient(tecomat_config(options={"clock_variable": "plcName"}))
    with pytest.raises(PlcValueError, match="plcName"):
        await bad.set_clock(datetime(2026, 1, 2, tzinfo=PRAGUE))
    for each in (client, bad):
        await each.close()


async def test_points_parsed_once_across_polls(
    tecomat_config: ConfigFactory, monkeypatch: pytest.MonkeyPatch
) -> None:
    """5,000 points: the second poll parses no path again (a cache of 4,096 thrashed: issue 19)."""
    sim = TecomatSimulator(bench=5000)
    await sim.start()
    client = TecomatClient(tecomat_config(port=sim.port))
    parsed: list[str] = []

    def counting(address: str) -> VariablePath:
        parsed.append(address)
        return parse_path(address)

    monkeypatch.setattr(client_module, "parse_path", counting)
    points = [Point(f"BENCH.V{index}", "INT") for index in range(5000)]
    try:
        await client.connect()
        first = await client.read(points)
        assert len(parsed) == 5000
        assert first.values[points[4999]].value == 4999 % 1000
        await client.read(points)
        assert len(parsed) == 5000
    finally:
        await client.close()
        await sim.stop()
