"""What the point form asks for select, button and alarm word points, and for conversions.

The point form (point_form.py) adds these fields and checks to its own: each platform gets
only what it needs (a value map for a select or an enum sensor, a pulse for a button, named
bits for an alarm word, a linear range where a number is shown, codes and invert where a
point is on or off). Imports go through the same check.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from homeassistant.components.sensor import CONF_STATE_CLASS
from homeassistant.const import CONF_DEVICE_CLASS, CONF_UNIT_OF_MEASUREMENT
from homeassistant.helpers.selector import (
    BooleanSelector,
    NumberSelector,
    NumberSelectorConfig,
    NumberSelectorMode,
    TextSelector,
    TextSelectorConfig,
)
import voluptuous as vol

from ..const import (
    BIT_LIMIT,
    CONF_AS_TEXT,
    CONF_BITS,
    CONF_INVERT,
    CONF_OFF_VALUE,
    CONF_ON_VALUE,
    CONF_PRECISION,
    CONF_PULSE,
    CONF_VALUE_MAP,
    PULSE_MAX,
    PULSE_MIN,
)
from ..plc import ValueKind
from .conversion import LINEAR_KEYS, InvalidPairs, format_pairs, parse_pairs
from .kinds import KINDS, Kind

PAIRS_FIELDS = (CONF_VALUE_MAP, CONF_BITS)
NUMBER_FIELDS = (*LINEAR_KEYS, CONF_PRECISION, CONF_ON_VALUE, CONF_OFF_VALUE, CONF_PULSE)
"""The numeric fields of these kinds (import reads them as numbers)."""
KIND_COLUMNS = (
    CONF_VALUE_MAP,
    *LINEAR_KEYS,
    CONF_PRECISION,
    CONF_INVERT,
    CONF_ON_VALUE,
    CONF_OFF_VALUE,
    CONF_PULSE,
    CONF_BITS,
)
"""The columns import and export add for these kinds, in export order (value maps in one
cell, `0=Off;1=Auto`)."""

NOT_WITH_MAP = (CONF_UNIT_OF_MEASUREMENT, CONF_DEVICE_CLASS, CONF_STATE_CLASS)
"""What a sensor that shows labels (an enum sensor) cannot have."""

_NUMBER = NumberSelector(NumberSelectorConfig(mode=NumberSelectorMode.BOX, step="any"))
_PAIRS = TextSelector(TextSelectorConfig(multiline=True))


def _codes(kind: ValueKind | None) -> bool:
    """True when on and off can be other codes than 1 and 0 (an integer point)."""
    return kind is None or kind is ValueKind.INTEGER


def kind_fields(platform: str, kind: ValueKind | None) -> dict[vol.Marker, Any]:
    """Return the fields the platform needs besides the point form's own (its kind's)."""
    fields: dict[vol.Marker, Any] = {}
    described = KINDS.get(platform, Kind(key=platform))
    if described.value_map == "required":
        fields[vol.Required(CONF_VALUE_MAP)] = _PAIRS
    elif described.value_map and _codes(kind):
        fields[vol.Optional(CONF_VALUE_MAP)] = _PAIRS
    if described.bits:
        fields[vol.Required(CONF_BITS)] = _PAIRS
    if described.linear and kind in (None, ValueKind.INTEGER, ValueKind.FLOAT):
        for key in (*LINEAR_KEYS, CONF_PRECISION):
            fields[vol.Optional(key)] = _NUMBER
    if described.invert:
        fields[vol.Required(CONF_INVERT, default=False)] = BooleanSelector()
    if described.as_text and kind is ValueKind.DURATION:
        fields[vol.Optional(CONF_AS_TEXT, default=False)] = BooleanSelector()
    if described.codes and _codes(kind):
        fields[vol.Optional(CONF_ON_VALUE)] = _NUMBER
        fields[vol.Optional(CONF_OFF_VALUE)] = _NUMBER
    if described.pulse:
        fields[vol.Optional(CONF_PULSE)] = NumberSelector(
            NumberSelectorConfig(
                min=PULSE_MIN, max=PULSE_MAX, step=0.1, mode=NumberSelectorMode.BOX
            )
        )
    return fields


def _pairs_data(
    key: str, text: Any, *, high: int | None
) -> tuple[dict[str, str], dict[str, str], dict[str, Any]]:
    """Check a value map or bit list; return errors, placeholders and the stored text."""
    try:
        pairs = parse_pairs(str(text), low=0 if high else None, high=high)
    except InvalidPairs as err:
        return {key: err.key}, {"pair": err.text}, {}
    return {}, {}, {key: format_pairs(pairs)}


def kind_data(
    platform: str, kind: ValueKind | None, values: Mapping[str, Any]
) -> tuple[dict[str, Any], dict[str, str], dict[str, str]]:
    """Check the fields of kind_fields; return the data to store, errors and placeholders."""
    allowed = kind_fields(platform, kind)
    asked = {str(marker) for marker in allowed}
    required = {str(marker) for marker in allowed if isinstance(marker, vol.Required)}
    data: dict[str, Any] = {}
    errors: dict[str, str] = {}
    placeholders: dict[str, str] = {}
    for key in PAIRS_FIELDS:
        if key in asked and values.get(key):
            found, details, stored = _pairs_data(
                key, values[key], high=BIT_LIMIT if key == CONF_BITS else None
            )
            errors |= found
            placeholders |= details
            data |= stored
        elif key in required:
            errors[key] = "map_empty"
    for key in NUMBER_FIELDS:
        if key in asked and values.get(key) is not None:
            data[key] = float(values[key])
    for key in (CONF_INVERT, CONF_AS_TEXT):
        if key in asked and values.get(key):
            data[key] = True  # stored only when set: older points compare unchanged
    errors |= _number_errors(data)
    shows_labels = KINDS.get(platform, Kind(key=platform)).value_map == "optional"
    if shows_labels and CONF_VALUE_MAP in data and any(map(values.get, NOT_WITH_MAP)):
        errors[CONF_VALUE_MAP] = "map_shows_labels"
    return data, errors, placeholders


def _number_errors(data: dict[str, Any]) -> dict[str, str]:
    """Check the linear range, the precision and the pulse; convert the whole numbers."""
    errors: dict[str, str] = {}
    given = [key for key in LINEAR_KEYS if key in data]
    if given and len(given) < len(LINEAR_KEYS):
        errors[next(key for key in LINEAR_KEYS if key not in data)] = "linear_incomplete"
    elif given and (data[LINEAR_KEYS[0]] == data[LINEAR_KEYS[1]]):
        errors[LINEAR_KEYS[1]] = "linear_empty"
    elif given and (data[LINEAR_KEYS[2]] == data[LINEAR_KEYS[3]]):
        errors[LINEAR_KEYS[3]] = "linear_empty"
    if CONF_PRECISION in data:
        if data[CONF_PRECISION] not in range(7):
            errors[CONF_PRECISION] = "precision_invalid"
        else:
            data[CONF_PRECISION] = int(data[CONF_PRECISION])
    if CONF_PULSE in data and not PULSE_MIN <= data[CONF_PULSE] <= PULSE_MAX:
        errors[CONF_PULSE] = "pulse_out_of_range"
    for key in (CONF_ON_VALUE, CONF_OFF_VALUE):
        if key in data and float(data[key]).is_integer():
            data[key] = int(data[key])
    return errors
