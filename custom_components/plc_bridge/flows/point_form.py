"""The point forms of the device flow, and the checks that turn a point's values into data.

One check (`point_data`) serves the forms, picking from the PLC and pasted imports alike.
"""

from __future__ import annotations

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

from ..const import (
    CONF_ADDRESS,
    CONF_DATA_TYPE,
    CONF_MAX,
    CONF_MIN,
    CONF_OFFSET,
    CONF_PLATFORM,
    CONF_READ_ONLY,
    CONF_SCALE,
    CONF_STEP,
)
from ..model.device_classes import device_classes, takes_unit, unit_selector
from ..model.kinds import CONTROLS, KINDS, NUMERIC, POINT_PLATFORMS
from ..model.point_kinds import kind_fields
from ..model.points import data_type_selector, suggested_platform
from ..model.poll_classes import has_poll_class, poll_field
from ..plc import BrowseItem, PlcAddressError, PlcClient, Point, ValueKind

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
            vol.Required(CONF_DATA_TYPE, default=client.data_types[0]): data_type_selector(client),
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
    described = KINDS[platform]
    if described.measures and takes_unit(platform, kind):
        fields[vol.Optional(CONF_STATE_CLASS)] = SelectSelector(
            SelectSelectorConfig(
                options=list(SensorStateClass),
                translation_key=CONF_STATE_CLASS,
                mode=SelectSelectorMode.DROPDOWN,
            )
        )
    if described.scaled and (kind is None or kind in NUMERIC):
        fields[vol.Required(CONF_SCALE, default=1.0)] = _NUMBER
        fields[vol.Required(CONF_OFFSET, default=0.0)] = _NUMBER
    if described.bounded:
        fields[vol.Optional(CONF_MIN)] = _NUMBER
        fields[vol.Optional(CONF_MAX)] = _NUMBER
        fields[vol.Optional(CONF_STEP)] = NumberSelector(
            NumberSelectorConfig(min=0, mode=NumberSelectorMode.BOX, step="any")
        )
    fields |= kind_fields(platform, kind)
    fields[vol.Required(CONF_READ_ONLY, default=platform not in CONTROLS)] = BooleanSelector()
    return vol.Schema(fields | (poll_field() if has_poll_class(platform) else {}))


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
