"""Tests of how points group into entities of several points (composite.py), without a PLC."""

from __future__ import annotations

from typing import Any

from custom_components.plc_bridge.composite import (
    as_platform,
    composites,
    group_errors,
    part_errors,
    touched,
)
from custom_components.plc_bridge.points import PointConfig


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
