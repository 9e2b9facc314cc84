"""The typed point: every stored key an attribute, read once, and the stored mapping given back
exactly as it was for every point shape the tests, the fixtures and the export files hold."""

from __future__ import annotations

from collections.abc import Iterator, Mapping
import importlib
import json
import math
from pathlib import Path
from typing import Any

import pytest

from bench.objects import machines
from custom_components.plc_bridge.model.config_keys import POINT
from custom_components.plc_bridge.model.conversion import Conversion
from custom_components.plc_bridge.model.points import FIELDS, PointConfig
from custom_components.plc_bridge.model.yaml_text import read_yaml
from custom_components.plc_bridge.plc import Point

TESTS = Path(__file__).resolve().parent.parent
FIXTURES = TESTS / "fixtures"
EXPORTS = [TESTS / "flows" / "export_response_js_yaml.txt"]


def _stored_points(found: Any, depth: int = 0) -> Iterator[Mapping[str, Any]]:
    """Every point's data in a structure: a (point id, data) pair or a machine's `points`."""
    if depth > 6:
        return
    pair = isinstance(found, tuple) and len(found) == 2 and isinstance(found[0], str)
    if pair and isinstance(found[1], dict) and "address" in found[1]:
        yield found[1]
        return
    if isinstance(found, Mapping):
        points = found.get("points")
        if points is None and isinstance(found.get("data"), Mapping):
            points = found["data"].get("points")
        if isinstance(points, Mapping):
            yield from (data for data in points.values() if isinstance(data, Mapping))
            return
        if found.get("subentry_type") == "point" and isinstance(found.get("data"), Mapping):
            yield found["data"]  # a version 1 point subentry
            return
        for value in found.values():
            yield from _stored_points(value, depth + 1)
    elif isinstance(found, list | tuple):
        for value in found:
            yield from _stored_points(value, depth + 1)


def _test_module_points() -> list[Mapping[str, Any]]:
    """The points every test module builds at module level (tests/entries.py's among them)."""
    found: list[Mapping[str, Any]] = []
    for path in sorted(TESTS.rglob("*.py")):
        module = importlib.import_module(
            ".".join(path.relative_to(TESTS.parent).with_suffix("").parts)
        )
        for key, value in vars(module).items():
            if not key.startswith("__"):
                found += _stored_points(value)
    return found


def _fixture_points(name: str) -> list[Mapping[str, Any]]:
    """The points of a stored entry of an older release (tests/fixtures)."""
    return list(_stored_points(json.loads((FIXTURES / name).read_text(encoding="utf-8"))))


def _export_points() -> list[Mapping[str, Any]]:
    """The points of the exported files the tests hold."""
    found: list[Mapping[str, Any]] = []
    for path in EXPORTS:
        found += _stored_points(read_yaml(path.read_text(encoding="utf-8")).data)
    return found


SOURCES = {
    "test modules": _test_module_points,
    "entry_0_1.json": lambda: _fixture_points("entry_0_1.json"),
    "entry_0_9.json": lambda: _fixture_points("entry_0_9.json"),
    "export files": _export_points,
    "bench machines": lambda: list(_stored_points(machines(16))),
}


def _exactly(value: Any) -> Any:
    """A value with its types spelled out, so 1 and 1.0 (or True and 1) differ."""
    if isinstance(value, Mapping):
        return [(key, _exactly(item)) for key, item in value.items()]
    if isinstance(value, list | tuple):
        return [type(value).__name__, *map(_exactly, value)]
    if isinstance(value, float) and math.isnan(value):
        return ("float", "nan")
    return (type(value).__name__, value)


def test_every_stored_key_is_an_attribute() -> None:
    """The keys a point may store (the pasted file's list) are the typed point's fields."""
    assert set(FIELDS) == set(POINT)
    assert set(FIELDS) - {"address", "data_type"} <= set(PointConfig.__slots__)
    assert not hasattr(PointConfig("p", "m", {"address": "VW0"}), "__dict__")


@pytest.mark.parametrize("source", SOURCES)
def test_round_trip_of_every_point_the_tests_hold(source: str) -> None:
    """Read and given back, each point is what was stored: keys in order, values and types."""
    stored = SOURCES[source]()
    assert stored
    for data in stored:
        config = PointConfig("p", "m", data)
        assert _exactly(config.stored()) == _exactly(data)
        assert PointConfig("p", "m", config.stored()) == config


def test_what_an_attribute_cannot_hold_comes_back_as_stored() -> None:
    """Odd stored values are read as their type, and given back as they were stored."""
    data: dict[str, Any] = {
        "scale": 1,
        "name": "Odd",
        "offset": "0.5",
        "precision": 2.0,
        "role": None,
        "poll": "often",
        "read_only": "yes",
        "mac": "00:11",
        "min": math.nan,
        "address": "VW0",
        "data_type": "signed",
    }
    config = PointConfig("p", "m", data)
    assert (config.scale, config.offset, config.precision) == (1, 0.5, 2)
    assert (config.role, config.poll, config.read_only) == (None, "normal", True)
    assert config.point == Point("VW0", "signed")
    assert set(config.extra or {}) == {"offset", "precision", "poll", "read_only", "mac", "min"}
    assert _exactly(config.stored()) == _exactly(data)


def test_absent_keys_read_as_defaults_and_stay_absent() -> None:
    """A point that stores little reads as the defaults; only what it stored comes back."""
    config = PointConfig("p", "m", {"address": "VW0"})
    assert (config.name, config.scale, config.offset, config.read_only) == ("", 1.0, 0.0, False)
    assert (config.poll, config.bit_pairs, config.extra) == ("normal", (), None)
    assert config.stored() == {"address": "VW0"}
    assert config != PointConfig("p", "m", {"address": "VW0", "scale": 1.0})


def test_parsed_values_are_read_once_and_shared() -> None:
    """Equal value maps and bit lists are parsed once: the points hold one tuple and conversion."""
    data = {"address": "VW0", "data_type": "signed", "bits": "0=Hot;3=Low", "value_map": "0=Off"}
    first = PointConfig("a", "m", json.loads(json.dumps(data)))
    second = PointConfig("b", "m", json.loads(json.dumps(data)))
    assert first.bit_pairs == ((0, "Hot"), (3, "Low"))
    assert first.bit_pairs is second.bit_pairs
    assert first.conversion is second.conversion
    assert first.conversion == Conversion(value_map=((0, "Off"),))
    assert first.point is second.point
    assert first.keys is second.keys
    scaled = PointConfig("c", "m", json.loads(json.dumps(data | {"scale": 2.0})))
    assert scaled.conversion != first.conversion
    assert scaled.conversion.value_map is first.conversion.value_map


def test_every_key_comes_back() -> None:
    """A point storing every key (as the forms store them) reads each and gives each back."""
    texts = ("name", "platform", "address", "data_type", "entity", "availability")
    texts += ("device_class", "unit_of_measurement", "state_class")
    data: dict[str, Any] = dict.fromkeys(FIELDS, 1.5) | dict.fromkeys(texts, "x")
    data |= dict.fromkeys(("read_only", "invert", "as_text"), True) | {"precision": 2}
    data |= {"poll": "slow", "role": "state", "value_map": "0=Off;1=On", "bits": "2=Hot"}
    config = PointConfig("p", "m", data)
    assert config.extra is None
    assert (config.as_text, config.supervision, config.travel_time) == (True, 1.5, 1.5)
    assert (config.availability, config.poll, config.bit_pairs) == ("x", "slow", ((2, "Hot"),))
    assert _exactly(config.stored()) == _exactly(data)
