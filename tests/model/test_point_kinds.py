"""The point form and tables for selects, enum sensors, buttons, alarm words and conversions."""

from __future__ import annotations

from typing import Any

import pytest

from custom_components.plc_bridge.flows.point_form import details_schema
from custom_components.plc_bridge.model.point_table import export_points, parse_points, point_order
from custom_components.plc_bridge.model.points import point_data
from custom_components.plc_bridge.plc import ValueKind
from custom_components.plc_bridge.plc.vendors import client_class

pytestmark = pytest.mark.no_pacing

SMART = client_class("s7_smart")
TECOMAT = client_class("tecomat")


def fields(platform: str, kind: ValueKind | None) -> set[str]:
    """Return the names of the details form's fields, besides the poll class every point has."""
    return {str(marker) for marker in details_schema(platform, kind).schema} - {"poll"}


def test_each_platform_asks_for_its_own() -> None:
    linear = {"raw_min", "raw_max", "shown_min", "shown_max", "precision"}
    assert fields("select", ValueKind.INTEGER) == {"value_map", "read_only"}
    assert fields("button", ValueKind.INTEGER) == {"on_value", "off_value", "pulse", "read_only"}
    assert fields("button", ValueKind.BOOL) == {"pulse", "read_only"}
    assert fields("event", ValueKind.INTEGER) == {"bits", "read_only"}
    assert {"value_map", *linear} <= fields("sensor", ValueKind.INTEGER)
    assert "value_map" not in fields("sensor", ValueKind.FLOAT)
    assert linear <= fields("number", ValueKind.INTEGER)
    assert {"invert", "on_value", "off_value"} <= fields("switch", ValueKind.INTEGER)
    assert "on_value" not in fields("switch", ValueKind.BOOL)
    assert "value_map" not in fields("text", ValueKind.TEXT)


def base(platform: str, address: str, data_type: str = "signed", **extra: Any) -> dict[str, Any]:
    """Return a point form's values."""
    return {"name": "P", "platform": platform, "address": address, "data_type": data_type} | extra


def test_select_stores_its_map_normalized() -> None:
    data, errors, _ = point_data(SMART, base("select", "VW30", value_map="0 = Off;\n1=Auto"))
    assert errors == {}
    assert data["value_map"] == "0=Off;1=Auto"
    assert data["read_only"] is False


@pytest.mark.parametrize(
    ("values", "errors", "placeholders"),
    [
        (base("select", "VW30"), {"value_map": "map_empty"}, {}),
        (
            base("select", "VW30", value_map="0=Off;Auto"),
            {"value_map": "map_not_a_pair"},
            {"pair": "Auto"},
        ),
        (base("select", "VD30", "float", value_map="0=Off"), {"platform": "needs_integer"}, {}),
        (base("event", "VW70", bits="64=Far"), {"bits": "map_out_of_range"}, {"pair": "64=Far"}),
        (base("button", "Q0.0", pulse=61), {"pulse": "pulse_out_of_range"}, {}),
        (base("button", "VB0", "string"), {"platform": "needs_bool_or_integer"}, {}),
        (base("number", "VW40", raw_min=0, raw_max=27648), {"shown_min": "linear_incomplete"}, {}),
        (
            base("number", "VW40", raw_min=5, raw_max=5, shown_min=0, shown_max=1),
            {"raw_max": "linear_empty"},
            {},
        ),
        (base("number", "VW40", precision=1.5), {"precision": "precision_invalid"}, {}),
        (base("button", "IB0", "unsigned"), {"platform": "address_not_writable"}, {}),
        (
            base("sensor", "VW32", value_map="0=Off", unit_of_measurement="°C"),
            {"value_map": "map_shows_labels"},
            {},
        ),
    ],
)
def test_refused(
    values: dict[str, Any], errors: dict[str, str], placeholders: dict[str, str]
) -> None:
    _, found, details = point_data(SMART, values)
    assert found == errors
    assert placeholders.items() <= details.items()


def test_button_and_number_data() -> None:
    data, errors, _ = point_data(SMART, base("button", "VW62", on_value=7.0, pulse=0.5))
    assert errors == {}
    assert (data["on_value"], data["pulse"]) == (7, 0.5)
    values = base("number", "VW40", raw_min=0, raw_max=27648, shown_min=0, shown_max=100)
    data, errors, _ = point_data(SMART, values | {"precision": 1.0})
    assert errors == {}
    assert (data["raw_max"], data["shown_max"], data["precision"]) == (27648, 100, 1)


def test_table_round_trips_every_kind() -> None:
    """One row per address; value maps and bits in one cell each."""
    table = (
        "name,address,data_type,platform,value_map,raw_min,raw_max,shown_min,shown_max,"
        "precision,invert,on_value,off_value,pulse,bits\n"
        'Mode,VW30,signed,select,"0=Off;1=Auto;2=Manual",,,,,,,,,,\n'
        "State,VW32,signed,sensor,-1=Fault;0=Idle,,,,,,,,,,\n"
        "Valve,VW40,signed,number,,0,27648,0,100,1,,,,,\n"
        "Contact,I0.0,signed,binary_sensor,,,,,,,yes,,,,\n"
        "Heater,VW50,signed,switch,,,,,,,,5,2,,\n"
        "Step,Q0.2,signed,button,,,,,,,,,,2,\n"
        'Alarms,VW70,signed,event,,,,,,,,,,,"0=Overheat;3=Low water"\n'
    )
    points, errors = parse_points(SMART, table)
    assert errors == []
    assert points[0]["value_map"] == "0=Off;1=Auto;2=Manual"
    assert points[0]["read_only"] is False
    assert points[1]["read_only"] is True
    assert points[3]["invert"] is True
    assert (points[4]["on_value"], points[5]["pulse"]) == (5, 2.0)
    assert points[6]["bits"] == "0=Overheat;3=Low water"
    exported = export_points(points)
    assert "'-1=Fault;0=Idle" in exported
    again, errors = parse_points(SMART, exported)
    assert errors == []
    assert again == sorted(points, key=point_order)


def test_tecomat_select() -> None:
    data, errors, _ = point_data(
        TECOMAT, base("select", "plcData.mode", "INT", value_map="0=Off;1=Auto")
    )
    assert errors == {}
    assert data["value_map"] == "0=Off;1=Auto"
