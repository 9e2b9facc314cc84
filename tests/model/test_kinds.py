"""Every entity kind is described once (model/kinds.py), and nothing else keeps a table of kinds.

The description gives each kind its platform module and its strings; the forms, the checks and
the entities read it. A module that lists kinds itself (a dict keyed by platform names, a set of
them, a comparison with one) would be a second place to change when a kind is added.
"""

from __future__ import annotations

import ast
import importlib
import json
from pathlib import Path
from typing import Any

from homeassistant.components.cover import CoverEntityFeature
from homeassistant.components.valve import ValveEntityFeature  # type: ignore[attr-defined]
from homeassistant.components.water_heater import (  # type: ignore[attr-defined]
    WaterHeaterEntityFeature,
)
import pytest

from custom_components.plc_bridge import PLATFORMS
from custom_components.plc_bridge.model.composite import part_data
from custom_components.plc_bridge.model.kinds import (
    COMPOSITE_PLATFORMS,
    KINDS,
    KINDS_IN_ORDER,
    POINT_PLATFORMS,
)
from custom_components.plc_bridge.model.points import read_only_errors
from custom_components.plc_bridge.plc.vendors import client_class

PACKAGE = Path(__file__).resolve().parents[2] / "custom_components" / "plc_bridge"
STRINGS = json.loads((PACKAGE / "strings.json").read_text(encoding="utf-8"))
PAGE = STRINGS["config_subentries"]["device"]["step"]["composite_entity"]
MENU = STRINGS["config_subentries"]["device"]["step"]["composite"]["menu_options"]
REMOVED = frozenset(
    {
        "ROLES",
        "NEEDS_ONE_OF",
        "LABELS",
        "TRAVEL_PLATFORMS",
        "SUPERVISED_PLATFORMS",
        "ALWAYS",
        "INVERTIBLE",
        "KIND_PLATFORMS",
        "KIND_CONTROLS",
        "PLATFORM_KINDS",
        "ALSO_SHOWN_ON",
        "UNPOLLED",
        "PLATFORMS",
        "POINT_PLATFORMS",
        "CONTROLS",
        "COVER_STATES",
    }
)
"""The per-kind tables the description replaced: only model/kinds.py may define them."""
ALLOWED = {
    ("binary_sensor.py", "event"): "the binary sensor platform makes an alarm word's bit sensors",
    ("model/migration.py", "sensor"): "old stored shapes are migrated as they were, once",
    ("model/migration.py", "number"): "old stored shapes are migrated as they were, once",
}
"""Modules that may name a kind, and why."""


def test_the_platforms_are_the_kinds() -> None:
    """The entry sets up exactly the platforms of the described kinds, each with its module."""
    assert {str(platform) for platform in PLATFORMS} == set(KINDS)
    for key in KINDS:
        module = importlib.import_module(f"custom_components.plc_bridge.{key}")
        assert callable(module.async_setup_entry), key
        assert module.PARALLEL_UPDATES in (0, 1), key


def test_every_kind_and_role_has_its_strings() -> None:
    """Each kind is named where it is chosen; each field of its page has a label and help in
    its section, and each section a name; its own device classes are named."""
    options = STRINGS["selector"]
    assert set(options["platform"]["options"]) == set(POINT_PLATFORMS)
    assert set(options["composite_platform"]["options"]) == set(COMPOSITE_PLATFORMS)
    assert set(MENU) == {f"entity_{kind}" for kind in COMPOSITE_PLATFORMS}
    for kind in KINDS_IN_ORDER:
        if kind.device_class is not None and not kind.single:
            named = options[f"{kind.key}_device_class"]["options"]
            assert set(named) == set(kind.device_class), kind.key
        for name, roles in kind.sections.items():
            texts = PAGE["sections"][name]
            assert texts["name"], name
            fields = [*(f"{role.key}_{s}" for role in roles for s in role.asks)]
            fields += [role.translation_key for role in roles]
            fields += [f"{role.translation_key}_data_type" for role in roles]
            for field in (*fields, *kind.shared(name)):
                assert field in texts["data"], (kind.key, field)
                assert field in texts["data_description"], (kind.key, field)


def test_orders_the_forms_list() -> None:
    """The point form keeps its order; the composite form lists entities of parts first."""
    assert POINT_PLATFORMS == (
        "sensor",
        "binary_sensor",
        "switch",
        "number",
        "datetime",
        "text",
        "select",
        "button",
        "event",
    )
    assert COMPOSITE_PLATFORMS[:3] == ("cover", "valve", "climate")
    assert COMPOSITE_PLATFORMS[-1] == "switch"


def test_a_valve_is_a_cover_without_tilt_and_step() -> None:
    """The valve's roles are the cover's, in the same order, less tilt and the step relay."""
    cover, valve = KINDS["cover"], KINDS["valve"]
    assert valve.role_keys == tuple(
        key for key in cover.role_keys if key not in ("tilt_position", "set_tilt_position", "step")
    )
    assert valve.needs_one_of == tuple(key for key in cover.needs_one_of if key != "step")


@pytest.mark.parametrize(
    ("kind", "written", "expected"),
    [
        ("cover", [], CoverEntityFeature(0)),
        (
            "cover",
            ["position"],
            CoverEntityFeature.OPEN | CoverEntityFeature.CLOSE | CoverEntityFeature.SET_POSITION,
        ),
        (
            "cover",
            ["set_position", "stop"],
            CoverEntityFeature.OPEN
            | CoverEntityFeature.CLOSE
            | CoverEntityFeature.STOP
            | CoverEntityFeature.SET_POSITION,
        ),
        ("cover", ["set_tilt_position"], CoverEntityFeature.SET_TILT_POSITION),
        ("valve", ["open", "close"], ValveEntityFeature.OPEN | ValveEntityFeature.CLOSE),
        (
            "water_heater",
            ["current_temperature", "target_temperature", "operation_mode", "on_off"],
            WaterHeaterEntityFeature.TARGET_TEMPERATURE
            | WaterHeaterEntityFeature.OPERATION_MODE
            | WaterHeaterEntityFeature.ON_OFF,
        ),
    ],
)
def test_roles_enable_their_features(kind: str, written: list[str], expected: int) -> None:
    """A part written enables its role's entity features, in the kind's own flag type."""
    assert KINDS[kind].features(written) == expected


@pytest.mark.parametrize("kind", [kind.key for kind in KINDS_IN_ORDER if kind.roles])
def test_written_roles_are_never_read_only(kind: str) -> None:
    """A role the entity writes refuses read only; one only read takes it."""
    for role in KINDS[kind].roles:
        refused = read_only_errors(role.checked_as, role.key, read_only=True)
        assert bool(refused) == role.written, (kind, role.key)


def test_role_errors_name_the_description() -> None:
    """A wrong role or label is told with the kind's own roles and labels, no fixed list."""
    client = client_class("s7_smart")
    base = {"name": "Tank", "address": "VW10", "data_type": "signed", "platform": "water_heater"}
    _, errors, wording = part_data(client, {**base, "role": "spin"})
    assert errors == {"role": "role_invalid"}
    assert wording["roles"] == "current_temperature, target_temperature, operation_mode, on_off"
    values = {**base, "role": "operation_mode", "value_map": "0=off;1=warm"}
    _, errors, wording = part_data(client, values)
    assert errors == {"value_map": "role_labels"}
    assert wording["labels"] == "eco, electric, performance, high_demand, heat_pump, gas, off"
    error = STRINGS["config_subentries"]["device"]["error"]
    assert "{roles}" in error["role_invalid"]
    assert "{labels}" in error["role_labels"]


def _kind_names(node: ast.AST) -> set[str]:
    """Return the kind names a literal collection or a comparison spells out."""
    if isinstance(node, ast.Dict):
        items: list[Any] = list(node.keys)
    elif isinstance(node, ast.Tuple | ast.List | ast.Set):
        items = list(node.elts)
    elif isinstance(node, ast.Compare):
        items = list(node.comparators)
    else:
        return set()
    return {
        item.value
        for item in items
        if isinstance(item, ast.Constant) and isinstance(item.value, str) and item.value in KINDS
    }


@pytest.mark.parametrize(
    "path",
    sorted(
        str(path.relative_to(PACKAGE))
        for path in PACKAGE.rglob("*.py")
        if path.relative_to(PACKAGE).as_posix() != "model/kinds.py"
    ),
)
def test_no_other_module_keeps_a_table_of_kinds(path: str) -> None:
    """Only the description lists kinds: no table of them, no test of a platform by name.

    A platform module registers its own name; anything else that names kinds is listed in
    ALLOWED with its reason.
    """
    tree = ast.parse((PACKAGE / path).read_text(encoding="utf-8"))
    own = Path(path).stem
    found: list[str] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Assign | ast.AnnAssign):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            found += [
                f"line {node.lineno}: {target.id} defined"
                for target in targets
                if isinstance(target, ast.Name) and target.id in REMOVED
            ]
        names = _kind_names(node)
        if isinstance(node, ast.Compare):
            names -= {own}
        elif len(names) < 2:
            continue
        found += [
            f"line {getattr(node, 'lineno', 0)}: names {name}"
            for name in sorted(names)
            if (Path(path).as_posix(), name) not in ALLOWED
        ]
    assert not found, found
