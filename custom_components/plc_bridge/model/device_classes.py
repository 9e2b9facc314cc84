"""Which device classes, units and state classes a point can carry, as Home Assistant checks.

The point form offers only what fits the entity type and the value, and refuses a combination
Home Assistant would log as wrong (a unit the class does not take, a state class without a number).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from enum import StrEnum
from typing import Any

from homeassistant.components.sensor import (
    CONF_STATE_CLASS,
    DEVICE_CLASS_STATE_CLASSES,
    SensorDeviceClass,
    SensorStateClass,
)
from homeassistant.components.sensor.const import STATE_CLASS_UNITS
from homeassistant.const import CONF_DEVICE_CLASS, CONF_UNIT_OF_MEASUREMENT
from homeassistant.helpers.selector import (
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
    TextSelector,
)

from ..plc import ValueKind
from .duration_units import UNITS as DURATION_UNITS
from .kinds import KINDS, NUMERIC

COUNTED = NUMERIC | {ValueKind.BOOL}
"""Kinds a sensor shows as a number (a true/false point as 1 or 0): unit and classes apply."""

DEVICE_CLASSES = {
    key: kind.device_class for key, kind in KINDS.items() if kind.single and kind.device_class
}
NOT_NUMERIC = {SensorDeviceClass.TIMESTAMP, SensorDeviceClass.DATE, SensorDeviceClass.ENUM}
"""Sensor classes whose state is no number: a numeric point cannot carry them."""
UNITS = {key: kind.units for key, kind in KINDS.items() if kind.units is not None}


def takes_unit(platform: str, kind: ValueKind | None) -> bool:
    """True when the platform shows the point as a number that can have a unit."""
    described = KINDS.get(platform)
    if described is None or not described.scaled:
        return False
    if described.measures:
        return kind is None or kind in COUNTED or kind is ValueKind.DURATION
    return True  # a duration: a time unit (seconds unless given)


def device_classes(platform: str, kind: ValueKind | None) -> list[str]:
    """Return the device classes a point of this kind can carry on the platform."""
    if platform not in DEVICE_CLASSES or kind is ValueKind.DURATION:
        return []  # a duration is always of class duration
    classes = [str(member) for member in DEVICE_CLASSES[platform]]
    if not KINDS[platform].measures:
        return classes
    if kind is ValueKind.DATETIME:
        return [SensorDeviceClass.TIMESTAMP.value]
    if not takes_unit(platform, kind):
        return []
    return [name for name in classes if name not in NOT_NUMERIC]


def allowed_units(platform: str, device_class: str | None) -> set[str | None] | None:
    """Return the units a device class takes (None in it: no unit), or None when any unit does."""
    table = UNITS.get(platform, {})
    if device_class is None or device_class not in table:
        return None
    return flat_units(table[device_class])


def flat_units(units: Iterable[Any]) -> set[str | None]:
    """Return a units set of Home Assistant's tables with its unit enums spelled out."""
    flat: set[str | None] = set()
    for unit in units:
        if isinstance(unit, type) and issubclass(unit, StrEnum):
            flat |= {member.value for member in unit}
        else:
            flat.add(unit)
    return flat


def unit_selector(platform: str, device_class: str | None) -> SelectSelector | TextSelector:
    """Return the unit field: the device class's units to choose from, else free text."""
    units = sorted(unit for unit in allowed_units(platform, device_class) or () if unit)
    if not units:
        return TextSelector()
    return SelectSelector(
        SelectSelectorConfig(
            options=units, custom_value=True, sort=True, mode=SelectSelectorMode.DROPDOWN
        )
    )


STATE_CLASSES = {
    str(key): set(map(str, value)) for key, value in DEVICE_CLASS_STATE_CLASSES.items()
}
"""The state classes each sensor device class allows."""
STATE_UNITS = {str(key): flat_units(value) for key, value in STATE_CLASS_UNITS.items()}
"""The units a state class needs (an angle: degrees)."""


def class_errors(
    platform: str, kind: ValueKind | None, values: Mapping[str, Any]
) -> tuple[dict[str, str], dict[str, str]]:
    """Check device class, unit and state class against each other, as Home Assistant does."""
    device_class = str(values.get(CONF_DEVICE_CLASS) or "") or None
    unit = str(values.get(CONF_UNIT_OF_MEASUREMENT) or "") or None
    state_class = str(values.get(CONF_STATE_CLASS) or "") or None
    errors: dict[str, str] = {}
    units: set[str | None] | None = None
    if device_class and device_class not in device_classes(platform, kind):
        errors[CONF_DEVICE_CLASS] = "invalid_device_class"
    elif unit and not takes_unit(platform, kind):
        errors[CONF_UNIT_OF_MEASUREMENT] = "unit_numeric"
    elif kind is ValueKind.DURATION and unit and unit not in DURATION_UNITS:
        errors[CONF_UNIT_OF_MEASUREMENT], units = "unit_not_valid", set(DURATION_UNITS)
    elif (units := allowed_units(platform, device_class)) is not None and unit not in units:
        errors[CONF_UNIT_OF_MEASUREMENT] = "unit_not_valid" if unit else "unit_required"
    measures = platform in KINDS and KINDS[platform].measures
    if state_class and (not measures or not takes_unit(platform, kind)):
        errors[CONF_STATE_CLASS] = "state_class_numeric_sensor"
    elif state_class not in (None, *SensorStateClass):
        errors[CONF_STATE_CLASS] = "invalid_state_class"
    elif state_class and state_class not in STATE_CLASSES.get(device_class or "", {state_class}):
        errors[CONF_STATE_CLASS] = "state_class_not_valid"
    elif state_class in STATE_UNITS and unit not in STATE_UNITS[state_class]:
        errors[CONF_UNIT_OF_MEASUREMENT] = "unit_not_valid_for_state_class"
        units = STATE_UNITS[state_class]
    return errors, {"units": ", ".join(sorted(str(item) for item in units or () if item))}
