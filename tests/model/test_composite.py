"""Tests of how points group into entities of several points (composite.py), without a PLC."""

from __future__ import annotations

from typing import Any

import pytest

from custom_components.plc_bridge.model.composite import (
    as_platform,
    assign_entities,
    composites,
    group_errors,
    part_errors,
    touched,
)
from custom_components.plc_bridge.model.point_table import export_points, parse_points, point_order
from custom_components.plc_bridge.model.points import PointConfig
from custom_components.plc_bridge.plc.vendors import client_class

pytestmark = pytest.mark.no_pacing

SMART = client_class("s7_smart")
TABLE = (
    "name,address,data_type,platform,role,value_map,raw_min,raw_max,shown_min,shown_max,"
    "min,max,step,scale,invert,pulse\n"
    "Shutter,VW40,signed,cover,position,,0,27648,0,100,,,,,,\n"
    "Shutter,VW42,signed,cover,set_position,,0,27648,0,100,,,,,yes,\n"
    "Shutter,Q0.4,signed,cover,open,,,,,,,,,,,\n"
    "Shutter,Q0.6,signed,cover,stop,,,,,,,,,,,1\n"
    "Shutter,I0.2,signed,cover,closed_limit,,,,,,,,,,,\n"
    "Shutter,VW44,signed,cover,status,0=closed;1=opening;2=open,,,,,,,,,,\n"
    "Boiler,VW50,signed,climate,current_temperature,,,,,,,,,0.1,,\n"
    "Boiler,VW52,signed,climate,target_temperature,,,,,,5,30,0.5,0.1,,\n"
    'Boiler,VW54,signed,climate,hvac_mode,"0=off;1=heat;2=cool",,,,,,,,,,\n'
    "Boiler,VW56,signed,climate,hvac_action,0=idle;1=heating,,,,,,,,,,\n"
)


def config(point_id: str, name: str, platform: str, role: str = "", sub: str = "a") -> PointConfig:
    """Return a configured point of a device subentry."""
    data: dict[str, Any] = {"name": name, "platform": platform, "address": "VW0"}
    if role:
        data["role"] = role
    return PointConfig(point_id, sub, data)


CONFIGS = {
    c.point_id: c
    for c in (
        config("p2", "Shutter", "cover", "open"),
        config("p1", "Shutter", "cover", "position"),
        config("p3", "Shutter", "cover", "close", sub="b"),
        config("p4", "Boiler", "climate", "target_temperature"),
        config("p5", "Shutter", "sensor"),
    )
}


def test_groups_by_device_platform_and_name() -> None:
    """Rows of one device sharing a platform and name are one entity, keyed by its first id."""
    found = composites(CONFIGS)
    assert set(found) == {"p1", "p3", "p4"}
    assert set(found["p1"].parts) == {"position", "open"}
    assert found["p4"].platform == "climate"


def test_touched_spreads_to_the_whole_entity() -> None:
    """An edited part rebuilds every point of its entity; a single point only itself."""
    assert touched(["p2"], CONFIGS, CONFIGS) == {"p1", "p2"}
    assert touched(["p5"], CONFIGS, CONFIGS) == {"p5"}
    gone = {key: value for key, value in CONFIGS.items() if key != "p2"}
    assert touched(["p2"], CONFIGS, gone) == {"p1", "p2"}


def test_part_checks() -> None:
    """A role must be the platform's; a mode map uses Home Assistant's own labels."""
    assert as_platform("cover", "open_limit") == "binary_sensor"
    assert as_platform("sensor", None) == "sensor"
    assert part_errors("cover", {"role": "spin"}) == {"role": "role_invalid"}
    assert part_errors("climate", {"role": "hvac_mode", "value_map": "0=off;1=warm"}) == {
        "value_map": "role_labels"
    }
    assert part_errors("climate", {"role": "hvac_mode", "value_map": "0=off;1=heat"}) == {}


def test_group_checks() -> None:
    """Each role once per entity, and at least one part that shows something."""
    rows = [
        {"name": "Shutter", "platform": "cover", "role": "open"},
        {"name": "Shutter", "platform": "cover", "role": "open"},
        {"name": "Boiler", "platform": "climate", "role": "hvac_action"},
        {"name": "Pump", "platform": "switch"},
    ]
    assert [(name, key) for name, key, _ in group_errors(rows)] == [
        ("Shutter", "role_repeated"),
        ("Boiler", "role_missing"),
    ]


def test_table_rows_make_parts_and_round_trip() -> None:
    """One row per address, each naming its role; reads are read only, commands written."""
    points, errors = parse_points(SMART, TABLE)
    assert errors == []
    by_role = {data["role"]: data for data in points}
    assert by_role["position"]["read_only"] is True
    assert by_role["set_position"]["read_only"] is False
    assert by_role["set_position"]["invert"] is True
    assert by_role["open"]["read_only"] is False
    assert by_role["stop"]["pulse"] == 1.0
    assert by_role["closed_limit"]["read_only"] is True
    assert by_role["status"]["read_only"] is True
    assert (by_role["target_temperature"]["min"], by_role["target_temperature"]["step"]) == (5, 0.5)
    assert by_role["hvac_mode"]["read_only"] is False
    assert {data["platform"] for data in points} == {"cover", "climate"}
    again, errors = parse_points(SMART, export_points(points))
    assert errors == []
    assert again == sorted(points, key=point_order)


@pytest.mark.parametrize(
    ("row", "problem"),
    [
        ("Shutter,VW46,signed,cover,spin,,,,,,,,,,,", "role_invalid"),
        ("Shutter,Q0.5,signed,cover,open,,,,,,,,,,,", "role_repeated"),
        ("Boiler,VW58,signed,climate,hvac_mode,0=off;1=warm,,,,,,,,,,", "role_labels"),
        ("Boiler,VW58,signed,climate,hvac_mode,,,,,,,,,,,", "map_empty"),
        ("Fan,VW58,signed,cover,stop,,,,,,,,,,,", "role_missing"),
        ("Shutter,IW0,signed,cover,set_position,,,,,,,,,,,", "address_not_writable"),
    ],
)
def test_table_refuses_bad_parts(row: str, problem: str) -> None:
    """A part with a wrong role, map or address, or an entity with a role twice, is refused."""
    points, errors = parse_points(SMART, TABLE + row + "\n")
    assert points == []
    assert [text.split(" ")[0] for _, text in errors] == [problem]


def test_entity_keys_are_kept() -> None:
    """Parts get their entity's key once; a part added later joins it; a split gets its own."""
    points: dict[str, dict[str, Any]] = {
        "b": {"name": "Shutter", "platform": "cover", "role": "open"},
        "c": {"name": "Shutter", "platform": "cover", "role": "close"},
        "d": {"name": "Pump", "platform": "switch"},
    }
    assign_entities(points)
    assert {points["b"]["entity"], points["c"]["entity"]} == {"b"}
    assert "entity" not in points["d"]
    points["a"] = {"name": "Shutter", "platform": "cover", "role": "stop"}
    points["c"] = {**points["c"], "name": "Gate"}
    assign_entities(points)
    assert [points[key]["entity"] for key in "abc"] == ["b", "b", "c"]
    configs = {key: PointConfig(key, "x", data) for key, data in points.items()}
    assert {group.key for group in composites(configs).values()} == {"b", "c"}


def test_table_adds_parts_to_an_entity_of_the_machine() -> None:
    """A pasted part joins the machine's entity of that name; its roles stay checked once."""
    points, _ = parse_points(SMART, TABLE)
    stop = "name,address,platform,role\nShutter,Q0.7,cover,close\n"
    added, errors = parse_points(SMART, stop, known=points)
    assert errors == []
    assert added[0]["role"] == "close"
    again = "name,address,platform,role\nShutter,Q0.7,cover,open\n"
    added, errors = parse_points(SMART, again, known=points)
    assert added == []
    assert errors == [(2, "role_repeated (Shutter, open)")]
