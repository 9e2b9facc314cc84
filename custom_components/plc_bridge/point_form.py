"""The point forms of the device flow, and the checks that turn a point's values into data.

One check (`point_data`) serves the forms, picking from the PLC and pasted imports alike.
"""

from __future__ import annotations

from collections.abc import Mapping
from enum import StrEnum
from typing import Any

from homeassistant.components.binary_sensor import (  # type: ignore[attr-defined]
    BinarySensorDeviceClass,
)
from homeassistant.components.number import NumberDeviceClass
from homeassistant.components.number.const import DEVICE_CLASS_UNITS as NUMBER_UNITS
from homeassistant.components.sensor import (
    CONF_STATE_CLASS,
    DEVICE_CLASS_STATE_CLASSES,
    SensorDeviceClass,
    SensorStateClass,
)
from homeassistant.components.sensor.const import DEVICE_CLASS_UNITS as SENSOR_UNITS
from homeassistant.components.switch import SwitchDeviceClass  # type: ignore[attr-defined]
from homeassistant.const import CONF_DEVICE_CLASS, CONF_NAME, CONF_UNIT_OF_MEASUREMENT
from homeassistant.helpers.selector import (
    BooleanSelector,
    NumberSelector,
    NumberSelectorConfig,
    NumberSelectorMode,
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
    TextSelector,
)
import voluptuous as vol

from .const import (
    CONF_ADDRESS,
    CONF_DATA_TYPE,
    CONF_MAX,
    CONF_MIN,
    CONF_OFFSET,
    CONF_PLATFORM,
    CONF_READ_ONLY,
    CONF_SCALE,
    CONF_STEP,
    POINT_PLATFORMS,
)
from .plc import BrowseItem, PlcAddressError, PlcClient, Point, ValueKind

NUMERIC = frozenset({ValueKind.INTEGER, ValueKind.FLOAT})
PLATFORM_KINDS: dict[str, tuple[frozenset[ValueKind], str]] = {
    "binary_sensor": (frozenset({ValueKind.BOOL}), "needs_bool"),
    "switch": (frozenset({ValueKind.BOOL}), "needs_bool"),
    "number": (NUMERIC, "needs_number"),
    "datetime": (frozenset({ValueKind.DATETIME}), "needs_datetime"),
    "text": (frozenset({ValueKind.TEXT}), "needs_text"),
}
"""The kinds of value a platform can show, and the error when a point is not one (sensor: all)."""

DEVICE_CLASSES: dict[str, type[StrEnum]] = {
    "sensor": SensorDeviceClass,
    "binary_sensor": BinarySensorDeviceClass,
    "switch": SwitchDeviceClass,
    "number": NumberDeviceClass,
}
NOT_NUMERIC = {SensorDeviceClass.TIMESTAMP, SensorDeviceClass.DATE, SensorDeviceClass.ENUM}
"""Sensor classes whose state is no number: a numeric point cannot carry them."""
UNITS: dict[str, Mapping[Any, set[Any]]] = {"sensor": SENSOR_UNITS, "number": NUMBER_UNITS}
SCALED = frozenset({"sensor", "number"})
"""Platforms whose numbers are scaled (and carry units)."""

_NUMBER = NumberSelector(NumberSelectorConfig(mode=NumberSelectorMode.BOX, step="any"))
BASE_FIELDS = (CONF_NAME, CONF_PLATFORM, CONF_ADDRESS, CONF_DATA_TYPE)


def base_schema(client: type[PlcClient]) -> vol.Schema:
    """Return the first point form: name, entity type, address and data type."""
    return vol.Schema(
        {
            vol.Required(CONF_NAME): TextSelector(),
            vol.Required(CONF_PLATFORM, default="sensor"): SelectSelector(
                SelectSelectorConfig(options=list(POINT_PLATFORMS), translation_key=CONF_PLATFORM)
            ),
            vol.Required(CONF_ADDRESS): TextSelector(),
            vol.Required(CONF_DATA_TYPE, default=client.data_types[0]): SelectSelector(
                SelectSelectorConfig(
                    options=list(client.data_types),
                    translation_key=CONF_DATA_TYPE,
                    mode=SelectSelectorMode.DROPDOWN,
                    custom_value=True,  # e.g. STRING[20]; the vendor's parser checks it
                )
            ),
        }
    )


def device_classes(platform: str, kind: ValueKind | None) -> list[str]:
    """Return the device classes a point of this kind can carry on the platform."""
    if platform not in DEVICE_CLASSES:
        return []
    classes = [str(member) for member in DEVICE_CLASSES[platform]]
    if platform != "sensor":
        return classes
    if kind is ValueKind.DATETIME:
        return [SensorDeviceClass.TIMESTAMP.value]
    if kind in (ValueKind.TEXT, ValueKind.BYTES):
        return []
    return [name for name in classes if name not in NOT_NUMERIC]


def details_schema(platform: str, kind: ValueKind | None) -> vol.Schema:
    """Return the second point form: the settings that fit the platform and the value."""
    fields: dict[vol.Marker, Any] = {}
    numeric = kind is None or kind in NUMERIC
    if platform in SCALED and numeric:
        fields[vol.Optional(CONF_UNIT_OF_MEASUREMENT)] = TextSelector()
    if classes := device_classes(platform, kind):
        fields[vol.Optional(CONF_DEVICE_CLASS)] = SelectSelector(
            SelectSelectorConfig(
                options=classes,
                translation_key=f"{platform}_device_class",
                mode=SelectSelectorMode.DROPDOWN,
                sort=True,
            )
        )
    if platform == "sensor" and numeric:
        fields[vol.Optional(CONF_STATE_CLASS)] = SelectSelector(
            SelectSelectorConfig(
                options=list(SensorStateClass),
                translation_key=CONF_STATE_CLASS,
                mode=SelectSelectorMode.DROPDOWN,
            )
        )
    if platform in SCALED and numeric:
        fields[vol.Required(CONF_SCALE, default=1.0)] = _NUMBER
        fields[vol.Required(CONF_OFFSET, default=0.0)] = _NUMBER
    if platform == "number":
        fields[vol.Optional(CONF_MIN)] = _NUMBER
        fields[vol.Optional(CONF_MAX)] = _NUMBER
        fields[vol.Optional(CONF_STEP)] = NumberSelector(
            NumberSelectorConfig(min=0, mode=NumberSelectorMode.BOX, step="any")
        )
    fields[vol.Required(CONF_READ_ONLY, default=platform in ("sensor", "binary_sensor"))] = (
        BooleanSelector()
    )
    return vol.Schema(fields)


def check_point(
    client: type[PlcClient], values: Mapping[str, Any]
) -> tuple[Point | None, ValueKind | None, dict[str, str], dict[str, str]]:
    """Check name, address, data type and entity type; return the normalized point and kind."""
    try:
        point = client.validate_point(
            Point(str(values[CONF_ADDRESS]).strip(), str(values[CONF_DATA_TYPE]).strip())
        )
    except PlcAddressError as err:
        return None, None, {CONF_ADDRESS: "invalid_address"}, {"error": str(err)}
    placeholders = {CONF_ADDRESS: point.address, CONF_DATA_TYPE: point.data_type}
    kind = client.value_kind(point)
    platform = str(values.get(CONF_PLATFORM, ""))
    errors: dict[str, str] = {}
    if platform not in POINT_PLATFORMS:
        errors[CONF_PLATFORM] = "invalid_platform"
    elif (
        platform in PLATFORM_KINDS and kind is not None and kind not in PLATFORM_KINDS[platform][0]
    ):
        errors[CONF_PLATFORM] = PLATFORM_KINDS[platform][1]
    if not str(values.get(CONF_NAME, "")).strip():
        errors[CONF_NAME] = "name_required"
    return point, kind, errors, placeholders


def unit_fits(platform: str, device_class: str | None, unit: str | None) -> bool:
    """True when the device class allows the unit (classes without a unit list allow any)."""
    units = UNITS.get(platform, {})
    if device_class is None or device_class not in units:
        return True
    allowed = units[device_class]
    enums = [item for item in allowed if isinstance(item, type) and issubclass(item, StrEnum)]
    return unit in allowed or any(unit in {member.value for member in enum} for enum in enums)


def point_data(
    client: type[PlcClient], values: Mapping[str, Any]
) -> tuple[dict[str, Any], dict[str, str], dict[str, str]]:
    """Check one whole point; return its data, the errors by field and their placeholders."""
    point, kind, errors, placeholders = check_point(client, values)
    if point is None:
        return {}, errors, placeholders
    platform = str(values[CONF_PLATFORM])
    device_class = values.get(CONF_DEVICE_CLASS) or None
    unit = values.get(CONF_UNIT_OF_MEASUREMENT) or None
    state_class = values.get(CONF_STATE_CLASS) or None
    if device_class and device_class not in device_classes(platform, kind):
        errors[CONF_DEVICE_CLASS] = "invalid_device_class"
    elif not unit_fits(platform, device_class, unit):
        errors[CONF_UNIT_OF_MEASUREMENT] = "unit_not_valid"
        placeholders["device_class"] = str(device_class)
    if state_class and (platform != "sensor" or (kind is not None and kind not in NUMERIC)):
        errors[CONF_STATE_CLASS] = "state_class_numeric_sensor"
    elif (
        state_class
        and device_class in DEVICE_CLASS_STATE_CLASSES
        and state_class not in DEVICE_CLASS_STATE_CLASSES[SensorDeviceClass(device_class)]
    ):
        errors[CONF_STATE_CLASS] = "state_class_not_valid"
    if float(values.get(CONF_SCALE, 1.0)) == 0:
        errors[CONF_SCALE] = "scale_zero"
    low, high = values.get(CONF_MIN), values.get(CONF_MAX)
    if low is not None and high is not None and float(low) >= float(high):
        errors[CONF_MAX] = "max_not_above_min"
    data: dict[str, Any] = {
        CONF_NAME: str(values[CONF_NAME]).strip(),
        CONF_PLATFORM: platform,
        CONF_ADDRESS: point.address,
        CONF_DATA_TYPE: point.data_type,
        CONF_SCALE: float(values.get(CONF_SCALE, 1.0)),
        CONF_OFFSET: float(values.get(CONF_OFFSET, 0.0)),
        CONF_READ_ONLY: bool(values.get(CONF_READ_ONLY, False)),
    }
    optional = {
        CONF_UNIT_OF_MEASUREMENT: unit,
        CONF_DEVICE_CLASS: device_class,
        CONF_STATE_CLASS: state_class,
    }
    data.update({key: value for key, value in optional.items() if value})
    for key in (CONF_MIN, CONF_MAX, CONF_STEP):
        if values.get(key) is not None:
            data[key] = float(values[key])
    return data, errors, placeholders


def browse_values(client: type[PlcClient], item: BrowseItem) -> dict[str, Any]:
    """Return a point's values for a variable the PLC published."""
    values: dict[str, Any] = {
        CONF_NAME: item.name or item.address,
        CONF_ADDRESS: item.address,
        CONF_DATA_TYPE: item.data_type,
        CONF_UNIT_OF_MEASUREMENT: item.unit,
        CONF_MIN: item.minimum,
        CONF_MAX: item.maximum,
        CONF_READ_ONLY: item.read_only,
        CONF_PLATFORM: item.platform
        or suggested_platform(client, item.address, item.data_type, read_only=item.read_only),
    }
    return {key: value for key, value in values.items() if value is not None}


def suggested_platform(
    client: type[PlcClient], address: str, data_type: str, *, read_only: bool = False
) -> str:
    """Return the platform that fits a point: writable ones get a control."""
    try:
        kind = client.value_kind(client.validate_point(Point(address, data_type)))
    except PlcAddressError:
        return "sensor"
    if kind is ValueKind.BOOL:
        return "binary_sensor" if read_only else "switch"
    if kind in NUMERIC:
        return "sensor" if read_only else "number"
    if kind is ValueKind.DATETIME and not read_only:
        return "datetime"
    if kind is ValueKind.TEXT and not read_only:
        return "text"
    return "sensor"
