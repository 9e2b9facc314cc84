"""The points of a PLC's device subentries, their devices, and entities that follow edits.

A device subentry holds any number of points; each point is one entity of the subentry's own
device, which hangs off the PLC's device. Adding, editing or removing points touches only the
entities of those points: the others keep their state, and the entry is not reloaded.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache
import sys
from typing import Any

from homeassistant.components.sensor import CONF_STATE_CLASS
from homeassistant.config_entries import ConfigEntry
from homeassistant.const import CONF_DEVICE_CLASS, CONF_NAME, CONF_UNIT_OF_MEASUREMENT
from homeassistant.helpers.selector import (
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
)

from ..const import (
    CONF_ADDRESS,
    CONF_DATA_TYPE,
    CONF_MAX,
    CONF_MIN,
    CONF_OFFSET,
    CONF_PLATFORM,
    CONF_POINTS,
    CONF_PULSE,
    CONF_READ_ONLY,
    CONF_ROLE,
    CONF_SCALE,
    CONF_STEP,
    PULSE_MAX,
    PULSE_MIN,
    SUBENTRY_DEVICE,
)
from ..plc import PlcAddressError, PlcClient, Point, ValueKind
from .device_classes import class_errors
from .kinds import CONTROLS, KINDS, NUMERIC, POINT_PLATFORMS
from .point_kinds import kind_data
from .poll_classes import has_poll_class, point_class, poll_data


@dataclass(frozen=True, slots=True)
class PointConfig:
    """One configured point: where it is stored and what the user set for it."""

    point_id: str
    subentry_id: str
    data: Mapping[str, Any]

    @property
    def point(self) -> Point:
        """The PLC address and data type the point reads (one object for equal points)."""
        return shared_point(str(self.data[CONF_ADDRESS]), str(self.data[CONF_DATA_TYPE]))

    @property
    def platform(self) -> str:
        """The entity platform that shows the point."""
        return str(self.data[CONF_PLATFORM])

    @property
    def platforms(self) -> tuple[str, ...]:
        """Every platform with entities of the point (an alarm word: also one per named bit)."""
        kind = KINDS.get(self.platform)
        return (self.platform, *(kind.also_shown_on if kind else ()))

    @property
    def name(self) -> str:
        """The point's (entity's) name."""
        return str(self.data[CONF_NAME])

    @property
    def poll(self) -> str:
        """The point's poll class: fast, normal or slow."""
        return point_class(self.data)

    @property
    def read_only(self) -> bool:
        """True when Home Assistant must never write the point."""
        return bool(self.data.get(CONF_READ_ONLY, False))


@lru_cache(maxsize=65536)
def shared_point(address: str, data_type: str) -> Point:
    """Return the point of an address and data type, one object for all that name it.

    The entities, the coordinator's poll plan and its results then hold one point, not a copy
    each; the data type's text (one of a few) is interned.
    """
    return Point(address, sys.intern(data_type))


def entry_points(entry: ConfigEntry[Any]) -> dict[str, PointConfig]:
    """Return every point of the entry's device subentries, by point id."""
    return {
        point_id: PointConfig(point_id, subentry.subentry_id, data)
        for subentry in entry.subentries.values()
        if subentry.subentry_type == SUBENTRY_DEVICE
        for point_id, data in subentry.data.get(CONF_POINTS, {}).items()
    }


def pulse_seconds(data: Mapping[str, Any]) -> float:
    """Return a point's pulse in seconds, kept within 0.1-60; 0 for a single write."""
    pulse = float(data.get(CONF_PULSE) or 0.0)
    return min(max(pulse, PULSE_MIN), PULSE_MAX) if pulse else 0.0


def point_key(data: Mapping[str, Any]) -> Point:
    """Return the (address, data type) that makes a point unique within a PLC."""
    return Point(data[CONF_ADDRESS], data[CONF_DATA_TYPE])


def never_read_only(platform: str, role: str | None = None) -> bool:
    """True for a point written to command an output: a button, or a part its entity writes.

    `platform` is the kind the point is checked as (a part's: the kind its role resembles), so
    a cover's open or set_position, a climate's mode or a light's brightness all count.
    """
    return (platform in KINDS and not KINDS[platform].polled) or (
        bool(role) and platform in CONTROLS
    )


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
    elif kind is not None and (accepted := KINDS[platform].value_kinds) and kind not in accepted:
        errors[CONF_PLATFORM] = KINDS[platform].kind_error
    elif platform in CONTROLS and not client.address_writable(point):
        errors[CONF_PLATFORM] = "address_not_writable"
    if not str(values.get(CONF_NAME, "")).strip():
        errors[CONF_NAME] = "name_required"
    return point, kind, errors, placeholders


def data_type_selector(client: type[PlcClient]) -> SelectSelector:
    """Return a data type field: the family's types by their labels (typed too where needed).

    Typed values are taken where the family's types take parameters (STRING[20]; the parser
    checks it). A field that takes a typed value shows the raw key once chosen, not its label: it is
    offered only where the family needs it.
    """
    return SelectSelector(
        SelectSelectorConfig(
            options=list(client.data_types),
            translation_key=CONF_DATA_TYPE,
            mode=SelectSelectorMode.DROPDOWN,
            custom_value=client.typed_data_types,
        )
    )


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
        if values.get(key) is not None and platform in KINDS and KINDS[platform].bounded:
            data[key] = float(values[key])
    role = str(values.get(CONF_ROLE) or "")
    errors |= read_only_errors(platform, role, data[CONF_READ_ONLY])
    extra, found, details = kind_data(platform, kind, values)
    classed, wrong = poll_data(values, polled=bool(role) or has_poll_class(platform))
    return data | extra | classed, errors | found | wrong, placeholders | details


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
