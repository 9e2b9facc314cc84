"""One point checked as a whole: entity type, device class, unit and state class fit together."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import homeassistant
from homeassistant.components.sensor import SensorDeviceClass
import pytest

from custom_components.plc_bridge.flows.point_form import browse_values, details_schema
from custom_components.plc_bridge.model.device_classes import DEVICE_CLASSES, device_classes
from custom_components.plc_bridge.model.kinds import POINT_PLATFORMS
from custom_components.plc_bridge.model.points import point_data, suggested_platform
from custom_components.plc_bridge.plc import BrowseItem, ValueKind
from custom_components.plc_bridge.plc.vendors import client_class

pytestmark = pytest.mark.no_pacing

SMART = client_class("s7_smart")
TECOMAT = client_class("tecomat")
SELECTORS = json.loads(
    (Path(__file__).parents[2] / "custom_components/plc_bridge/strings.json").read_text()
)["selector"]
TANK = {"name": "Tank", "platform": "sensor", "address": "VD100", "data_type": "float"}
SETPOINT = {"name": "Setpoint", "platform": "number", "address": "VW20", "data_type": "signed"}
STAMP = {"name": "Stamp", "platform": "sensor", "address": "plcData.varDT", "data_type": "DT"}


def fields(schema: Any) -> dict[str, Any]:
    """Return a form's fields by name."""
    return {str(marker): selector for marker, selector in schema.schema.items()}


def test_numeric_sensor_offers_no_timestamp_date_or_enum() -> None:
    """A number cannot be a timestamp, a date or an enum; a date and time only a timestamp."""
    numeric = device_classes("sensor", ValueKind.FLOAT)
    assert "temperature" in numeric
    assert not {"timestamp", "date", "enum"} & set(numeric)
    assert device_classes("sensor", ValueKind.DATETIME) == ["timestamp"]
    assert device_classes("sensor", ValueKind.TEXT) == []
    assert device_classes("datetime", ValueKind.DATETIME) == []
    assert device_classes("switch", ValueKind.BOOL) == ["outlet", "switch"]


@pytest.mark.parametrize("platform", sorted(DEVICE_CLASSES))
def test_every_offered_class_has_home_assistants_name(platform: str) -> None:
    """The dropdown shows each class by the name Home Assistant gives it, never a raw key."""
    ours = SELECTORS[f"{platform}_device_class"]["options"]
    english = Path(homeassistant.__file__).parent / "components" / platform / "translations"
    theirs = json.loads((english / "en.json").read_text())["entity_component"]
    for kind in (*ValueKind, None):
        for name in device_classes(platform, kind):
            assert ours[name] == theirs.get(name, {}).get("name", ours[name]), name
    assert ours.get("absolute_humidity", "Absolute humidity") == "Absolute humidity"


def test_details_fit_the_entity_type() -> None:
    """Each entity type gets only its own settings (and a poll class); a class's units too."""
    assert set(fields(details_schema("binary_sensor", ValueKind.BOOL))) == {
        "device_class",
        "invert",
        "read_only",
        "poll",
    }
    assert set(fields(details_schema("text", ValueKind.TEXT))) == {"read_only", "poll"}
    number = fields(details_schema("number", ValueKind.INTEGER))
    assert {"min", "max", "step", "scale", "offset", "unit_of_measurement"} <= set(number)
    assert "state_class" not in number
    sensor = fields(details_schema("sensor", ValueKind.FLOAT, "temperature"))
    assert sensor["device_class"].config["translation_key"] == "sensor_device_class"
    assert set(sensor["unit_of_measurement"].config["options"]) == {"°C", "°F", "K"}
    assert sensor["unit_of_measurement"].config["custom_value"] is True
    stamp = fields(details_schema("sensor", ValueKind.DATETIME))
    assert stamp["device_class"].config["options"] == ["timestamp"]
    assert "unit_of_measurement" not in stamp


def check(client: Any, values: dict[str, Any]) -> tuple[dict[str, Any], dict[str, str], Any]:
    """Return point_data's result."""
    return point_data(client, values)


@pytest.mark.parametrize(
    ("values", "errors", "units"),
    [
        ({**TANK, "device_class": "timestamp"}, {"device_class": "invalid_device_class"}, ""),
        ({**TANK, "device_class": "date"}, {"device_class": "invalid_device_class"}, ""),
        ({**TANK, "device_class": "enum"}, {"device_class": "invalid_device_class"}, ""),
        (
            {**TANK, "device_class": "temperature", "unit_of_measurement": "bar"},
            {"unit_of_measurement": "unit_not_valid"},
            "K, °C, °F",
        ),
        (
            {**TANK, "device_class": "temperature"},
            {"unit_of_measurement": "unit_required"},
            "K, °C, °F",
        ),
        (
            {**TANK, "device_class": "temperature", "unit_of_measurement": "°C"}
            | {"state_class": "total_increasing"},
            {"state_class": "state_class_not_valid"},
            "K, °C, °F",
        ),
        ({**TANK, "state_class": "average"}, {"state_class": "invalid_state_class"}, ""),
        (
            {**TANK, "state_class": "measurement_angle", "unit_of_measurement": "rad"},
            {"unit_of_measurement": "unit_not_valid_for_state_class"},
            "°",
        ),
        (
            {**SETPOINT, "device_class": "temperature", "unit_of_measurement": "bar"},
            {"unit_of_measurement": "unit_not_valid"},
            "K, °C, °F",
        ),
        (
            {**SETPOINT, "state_class": "measurement"},
            {"state_class": "state_class_numeric_sensor"},
            "",
        ),
        (
            {"name": "Door", "platform": "binary_sensor", "address": "I0.0", "data_type": "signed"}
            | {"unit_of_measurement": "°C"},
            {"unit_of_measurement": "unit_numeric"},
            "",
        ),
        ({**TANK, "scale": 0}, {"scale": "scale_zero"}, ""),
        ({**SETPOINT, "min": 10, "max": 10}, {"max": "max_not_above_min"}, ""),
        ({**TANK, "platform": "switch"}, {"platform": "needs_bool"}, ""),
        ({**TANK, "platform": "lamp"}, {"platform": "invalid_platform"}, ""),
        ({**TANK, "name": " "}, {"name": "name_required"}, ""),
    ],
)
def test_refused(values: dict[str, Any], errors: dict[str, str], units: str) -> None:
    """A class the value cannot carry, units and state classes that do not fit are refused."""
    _, found, placeholders = check(SMART, values)
    assert found == errors
    assert placeholders.get("units", "") == units


def test_invalid_address_says_why() -> None:
    """The parser's own words come back as the placeholder."""
    data, errors, placeholders = check(SMART, {**TANK, "address": "VX7"})
    assert (data, errors) == ({}, {"address": "invalid_address"})
    assert "VX7" in placeholders["error"]


@pytest.mark.parametrize(
    "values",
    [
        {**TANK, "device_class": "temperature", "unit_of_measurement": "°F"}
        | {"state_class": "measurement"},
        {**TANK, "device_class": "aqi"},  # a class without a unit
        {**TANK, "unit_of_measurement": "bar", "state_class": "total"},  # no class: any unit
        {**TANK, "state_class": "measurement_angle", "unit_of_measurement": "°"},
        {**SETPOINT, "device_class": "temperature", "unit_of_measurement": "°C"},
        {"name": "On", "platform": "sensor", "address": "Q0.0", "data_type": "signed"}
        | {"device_class": "power_factor", "state_class": "measurement"},  # 1 or 0
    ],
)
def test_accepted(values: dict[str, Any]) -> None:
    """Fitting combinations pass."""
    assert check(SMART, values)[1] == {}


def test_datetime_sensor_is_a_timestamp_only() -> None:
    """A date and time point may be a sensor with the timestamp class, and nothing else."""
    assert check(TECOMAT, {**STAMP, "device_class": "timestamp"})[1] == {}
    assert check(TECOMAT, {**STAMP, "device_class": "temperature"})[1] == {
        "device_class": "invalid_device_class"
    }
    assert check(TECOMAT, {**STAMP, "unit_of_measurement": "s"})[1] == {
        "unit_of_measurement": "unit_numeric"
    }


def test_data_is_normalized_and_only_what_fits() -> None:
    """Addresses come back as the parser writes them; limits only for numbers."""
    data, errors, _ = check(SMART, {**TANK, "address": "vd100", "min": 1.0, "max": 2.0})
    assert errors == {}
    assert data == {
        "name": "Tank",
        "platform": "sensor",
        "address": "VD100",
        "data_type": "float",
        "scale": 1.0,
        "offset": 0.0,
        "read_only": False,
    }
    data, _, _ = check(SMART, {**SETPOINT, "min": 0, "max": 100, "step": 0.5})
    assert (data["min"], data["max"], data["step"]) == (0.0, 100.0, 0.5)


def test_browse_values() -> None:
    """A published object keeps its title, unit, limits and platform; a bit drops the unit."""
    item = BrowseItem(
        address="Main.myObject3.value",
        data_type="REAL",
        name="requested temperature",
        unit="°C",
        minimum=10.0,
        maximum=30.0,
        platform="number",
    )
    data, errors, _ = point_data(TECOMAT, browse_values(TECOMAT, item))
    assert errors == {}
    assert (data["name"], data["unit_of_measurement"], data["min"]) == (
        "requested temperature",
        "°C",
        10.0,
    )
    flag = BrowseItem(address="plcData.varBool0", data_type="BOOL", unit="-", read_only=True)
    values = browse_values(TECOMAT, flag)
    assert values["platform"] == "binary_sensor"
    assert "unit_of_measurement" not in values
    assert point_data(TECOMAT, values)[1] == {}


@pytest.mark.parametrize(
    ("address", "data_type", "read_only", "platform"),
    [
        ("Q0.0", "signed", False, "switch"),
        ("I0.0", "signed", True, "binary_sensor"),
        ("VW10", "signed", False, "number"),
        ("VW10", "signed", True, "sensor"),
        ("VB200", "string", False, "text"),
        ("DATE", "signed", False, "datetime"),
        ("VX1", "signed", False, "sensor"),
    ],
)
def test_suggested_platform(address: str, data_type: str, read_only: bool, platform: str) -> None:
    """Writable points get a control, read-only ones a sensor; a bad address a sensor."""
    assert suggested_platform(SMART, address, data_type, read_only=read_only) == platform
    assert platform in POINT_PLATFORMS


def test_every_sensor_class_is_sorted_out() -> None:
    """Each sensor class is offered to numbers, or is one of the three that are not numbers."""
    offered = set(device_classes("sensor", ValueKind.INTEGER))
    assert set(SensorDeviceClass) - offered == {"timestamp", "date", "enum"}
