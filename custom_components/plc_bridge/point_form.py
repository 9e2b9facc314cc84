"""The point forms of the device flow, and the checks that turn a point's values into data.

One check (`point_data`) serves the forms, picking from the PLC and pasted imports alike.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from homeassistant.components.sensor import (
    CONF_STATE_CLASS,
    SensorStateClass,
)
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
    CONF_ROLE,
    CONF_SCALE,
    CONF_STEP,
    POINT_PLATFORMS,
)
from .device_classes import (
    NUMERIC,
    class_errors,
    device_classes,
    takes_unit,
    unit_selector,
)
from .plc import BrowseItem, PlcAddressError, PlcClient, Point, ValueKind
from .point_kinds import KIND_CONTROLS, KIND_PLATFORMS, kind_data, kind_fields
from .poll_classes import has_poll_class, poll_data, poll_field

PLATFORM_KINDS: dict[str, tuple[frozenset[ValueKind], str]] = {
    "binary_sensor": (frozenset({ValueKind.BOOL}), "needs_bool"),
    "switch": (frozenset({ValueKind.BOOL}), "needs_bool"),
    "number": (NUMERIC | {ValueKind.DURATION}, "needs_number"),
    "datetime": (frozenset({ValueKind.DATETIME}), "needs_datetime"),
    "text": (frozenset({ValueKind.TEXT, ValueKind.DURATION}), "needs_text"),  # hh:mm:ss.zzz
    **KIND_PLATFORMS,
}
"""The kinds of value a platform can show, and the error when a point is not one (sensor: all)."""
CONTROLS = frozenset({"switch", "number", "datetime", "text"}) | KIND_CONTROLS
"""Platforms that write their point: a point only gets one where it asks for it."""

_NUMBER = NumberSelector(NumberSelectorConfig(mode=NumberSelectorMode.BOX, step="any"))
BASE_FIELDS = (CONF_NAME, CONF_PLATFORM, CONF_ADDRESS, CONF_DATA_TYPE)


def point_key(data: Mapping[str, Any]) -> Point:
    """Return the (address, data type) that makes a point unique within a PLC."""
    return Point(data[CONF_ADDRESS], data[CONF_DATA_TYPE])


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


def details_schema(
    platform: str, kind: ValueKind | None, device_class: str | None = None
) -> vol.Schema:
    """Return the second point form: the settings that fit the platform and the value."""
    fields: dict[vol.Marker, Any] = {}
    if classes := device_classes(platform, kind):
        fields[vol.Optional(CONF_DEVICE_CLASS)] = SelectSelector(
            SelectSelectorConfig(
                options=classes,
                translation_key=f"{platform}_device_class",
                mode=SelectSelectorMode.DROPDOWN,
                sort=True,
            )
        )
    if takes_unit(platform, kind):
        unit_class = "duration" if kind is ValueKind.DURATION else device_class
        fields[vol.Optional(CONF_UNIT_OF_MEASUREMENT)] = unit_selector(platform, unit_class)
    if platform == "sensor" and takes_unit(platform, kind):
        fields[vol.Optional(CONF_STATE_CLASS)] = SelectSelector(
            SelectSelectorConfig(
                options=list(SensorStateClass),
                translation_key=CONF_STATE_CLASS,
                mode=SelectSelectorMode.DROPDOWN,
            )
        )
    if platform in ("sensor", "number") and (kind is None or kind in NUMERIC):
        fields[vol.Required(CONF_SCALE, default=1.0)] = _NUMBER
        fields[vol.Required(CONF_OFFSET, default=0.0)] = _NUMBER
    if platform == "number":
        fields[vol.Optional(CONF_MIN)] = _NUMBER
        fields[vol.Optional(CONF_MAX)] = _NUMBER
        fields[vol.Optional(CONF_STEP)] = NumberSelector(
            NumberSelectorConfig(min=0, mode=NumberSelectorMode.BOX, step="any")
        )
    fields |= kind_fields(platform, kind)
    fields[vol.Required(CONF_READ_ONLY, default=platform not in CONTROLS)] = BooleanSelector()
    return vol.Schema(fields | (poll_field() if has_poll_class(platform) else {}))


def never_read_only(platform: str, role: str | None = None) -> bool:
    """True for a point written to command an output: a button, or a part its entity writes.

    `platform` is the kind the point is checked as (a part's: the kind its role resembles), so
    a cover's open or set_position, a climate's mode or a light's brightness all count.
    """
    return platform == "button" or (bool(role) and platform in CONTROLS)


def read_only_errors(platform: str, role: str | None, read_only: bool) -> dict[str, str]:
    """Refuse a read-only point that commands an output (the forms, tables and file ask this)."""
    return (
        {CONF_READ_ONLY: "command_read_only"}
        if read_only and never_read_only(platform, role)
        else {}
    )


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
    elif platform in CONTROLS and not client.address_writable(point):
        errors[CONF_PLATFORM] = "address_not_writable"
    if not str(values.get(CONF_NAME, "")).strip():
        errors[CONF_NAME] = "name_required"
    return point, kind, errors, placeholders


def point_data(
    client: type[PlcClient], values: Mapping[str, Any]
) -> tuple[dict[str, Any], dict[str, str], dict[str, str]]:
    """Check one whole point; return its data, the errors by field and their placeholders."""
    point, kind, errors, placeholders = check_point(client, values)
    if point is None:
        return {}, errors, placeholders
    platform = str(values[CONF_PLATFORM])
    found, details = class_errors(platform, kind, values)
    errors |= found
    placeholders |= details
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
    for key in (CONF_UNIT_OF_MEASUREMENT, CONF_DEVICE_CLASS, CONF_STATE_CLASS):
        if values.get(key):
            data[key] = str(values[key])
    for key in (CONF_MIN, CONF_MAX, CONF_STEP):
        if values.get(key) is not None and platform == "number":
            data[key] = float(values[key])
    role = str(values.get(CONF_ROLE) or "")
    errors |= read_only_errors(platform, role, data[CONF_READ_ONLY])
    extra, found, details = kind_data(platform, kind, values)
    classed, wrong = poll_data(values, polled=bool(role) or has_poll_class(platform))
    return data | extra | classed, errors | found | wrong, placeholders | details


def browse_values(client: type[PlcClient], item: BrowseItem) -> dict[str, Any]:
    """Return a point's values for a variable the PLC published."""
    values: dict[str, Any] = {
        CONF_NAME: item.name or item.address,
        CONF_ADDRESS: item.address,
        CONF_DATA_TYPE: item.data_type,
        CONF_MIN: item.minimum,
        CONF_MAX: item.maximum,
        CONF_READ_ONLY: item.read_only,
        CONF_PLATFORM: item.platform
        or suggested_platform(client, item.address, item.data_type, read_only=item.read_only),
    }
    try:
        kind = client.value_kind(client.validate_point(Point(item.address, item.data_type)))
    except PlcAddressError:
        kind = None
    if item.unit and takes_unit(values[CONF_PLATFORM], kind):
        values[CONF_UNIT_OF_MEASUREMENT] = item.unit
    return {key: value for key, value in values.items() if value is not None}


def suggested_platform(
    client: type[PlcClient], address: str, data_type: str, *, read_only: bool = False
) -> str:
    """Return the platform that fits a point: writable ones get a control, inputs never."""
    try:
        point = client.validate_point(Point(address, data_type))
    except PlcAddressError:
        return "sensor"
    kind = client.value_kind(point)
    read_only = read_only or not client.address_writable(point)
    if kind is ValueKind.BOOL:
        return "binary_sensor" if read_only else "switch"
    if kind in NUMERIC or kind is ValueKind.DURATION:
        return "sensor" if read_only else "number"
    if kind is ValueKind.DATETIME and not read_only:
        return "datetime"
    if kind is ValueKind.TEXT and not read_only:
        return "text"
    return "sensor"
