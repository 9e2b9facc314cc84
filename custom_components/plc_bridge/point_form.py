"""The point form of the subentry flow: its fields, and the checks that turn it into data."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from homeassistant.components.binary_sensor import BinarySensorDeviceClass
from homeassistant.components.number import NumberDeviceClass
from homeassistant.components.sensor import (
    CONF_STATE_CLASS,
    SensorDeviceClass,
    SensorStateClass,
)
from homeassistant.components.switch import SwitchDeviceClass
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

DEVICE_CLASSES: dict[str, frozenset[str]] = {
    "sensor": frozenset(SensorDeviceClass),
    "binary_sensor": frozenset(BinarySensorDeviceClass),
    "switch": frozenset(SwitchDeviceClass),
    "number": frozenset(NumberDeviceClass),
    "datetime": frozenset(),
    "text": frozenset(),
}

_NUMBER = NumberSelector(NumberSelectorConfig(mode=NumberSelectorMode.BOX, step="any"))


def point_schema(client: type[PlcClient]) -> vol.Schema:
    """Return the point form for a vendor: its data types in the type selector."""
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
            vol.Optional(CONF_UNIT_OF_MEASUREMENT): TextSelector(),
            vol.Optional(CONF_DEVICE_CLASS): SelectSelector(
                SelectSelectorConfig(
                    options=sorted(set().union(*DEVICE_CLASSES.values())),
                    mode=SelectSelectorMode.DROPDOWN,
                )
            ),
            vol.Optional(CONF_STATE_CLASS): SelectSelector(
                SelectSelectorConfig(
                    options=list(SensorStateClass),
                    translation_key=CONF_STATE_CLASS,
                    mode=SelectSelectorMode.DROPDOWN,
                )
            ),
            vol.Required(CONF_SCALE, default=1.0): _NUMBER,
            vol.Required(CONF_OFFSET, default=0.0): _NUMBER,
            vol.Optional(CONF_MIN): _NUMBER,
            vol.Optional(CONF_MAX): _NUMBER,
            vol.Optional(CONF_STEP): NumberSelector(
                NumberSelectorConfig(min=0, mode=NumberSelectorMode.BOX, step="any")
            ),
            vol.Required(CONF_READ_ONLY, default=False): BooleanSelector(),
        }
    )


def point_data(
    client: type[PlcClient], user_input: Mapping[str, Any]
) -> tuple[dict[str, Any], dict[str, str], dict[str, str]]:
    """Check a submitted point form; return the subentry data, the errors and their placeholders.

    The vendor's parser checks and normalizes the address; the client says what kind of value
    the point holds, which decides the platforms that fit it.
    """
    try:
        point = client.validate_point(
            Point(str(user_input[CONF_ADDRESS]).strip(), user_input[CONF_DATA_TYPE])
        )
    except PlcAddressError as err:
        return {}, {CONF_ADDRESS: "invalid_address"}, {"error": str(err)}
    platform: str = user_input[CONF_PLATFORM]
    kind = client.value_kind(point)
    errors: dict[str, str] = {}
    if platform in PLATFORM_KINDS and kind is not None and kind not in PLATFORM_KINDS[platform][0]:
        errors[CONF_PLATFORM] = PLATFORM_KINDS[platform][1]
    if (
        user_input.get(CONF_DEVICE_CLASS)
        and user_input[CONF_DEVICE_CLASS] not in DEVICE_CLASSES[platform]
    ):
        errors[CONF_DEVICE_CLASS] = "invalid_device_class"
    if user_input.get(CONF_STATE_CLASS) and (
        platform != "sensor" or (kind is not None and kind not in NUMERIC)
    ):
        errors[CONF_STATE_CLASS] = "state_class_numeric_sensor"
    if user_input[CONF_SCALE] == 0:
        errors[CONF_SCALE] = "scale_zero"
    low, high = user_input.get(CONF_MIN), user_input.get(CONF_MAX)
    if low is not None and high is not None and low >= high:
        errors[CONF_MAX] = "max_not_above_min"
    data: dict[str, Any] = {
        CONF_PLATFORM: platform,
        CONF_ADDRESS: point.address,
        CONF_DATA_TYPE: point.data_type,
        CONF_SCALE: float(user_input[CONF_SCALE]),
        CONF_OFFSET: float(user_input[CONF_OFFSET]),
        CONF_READ_ONLY: bool(user_input[CONF_READ_ONLY]),
    }
    for key in (CONF_UNIT_OF_MEASUREMENT, CONF_DEVICE_CLASS, CONF_STATE_CLASS):
        if user_input.get(key):
            data[key] = user_input[key]
    for key in (CONF_MIN, CONF_MAX, CONF_STEP):
        if user_input.get(key) is not None:
            data[key] = float(user_input[key])
    placeholders = {CONF_ADDRESS: point.address, CONF_DATA_TYPE: point.data_type}
    return data, errors, placeholders


def browse_values(client: type[PlcClient], item: BrowseItem) -> dict[str, Any]:
    """Return the point form's suggested values for a variable the PLC published."""
    values: dict[str, Any] = {
        CONF_NAME: item.name or item.address,
        CONF_ADDRESS: item.address,
        CONF_DATA_TYPE: item.data_type,
        CONF_UNIT_OF_MEASUREMENT: item.unit,
        CONF_MIN: item.minimum,
        CONF_MAX: item.maximum,
        CONF_READ_ONLY: item.read_only,
        CONF_PLATFORM: item.platform or suggested_platform(client, item),
    }
    return {key: value for key, value in values.items() if value is not None}


def suggested_platform(client: type[PlcClient], item: BrowseItem) -> str:
    """Return the platform that fits a published variable: writable ones get a control."""
    try:
        kind = client.value_kind(client.validate_point(Point(item.address, item.data_type)))
    except PlcAddressError:
        return "sensor"
    if kind is ValueKind.BOOL:
        return "binary_sensor" if item.read_only else "switch"
    if kind in NUMERIC and not item.read_only:
        return "number"
    if kind is ValueKind.DATETIME and not item.read_only:
        return "datetime"
    if kind is ValueKind.TEXT and not item.read_only:
        return "text"
    return "sensor"
