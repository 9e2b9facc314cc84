"""The points of a PLC's device subentries, their devices, and entities that follow edits.

A device subentry holds any number of points; each point is one entity of the subentry's own
device, which hangs off the PLC's device. Adding, editing or removing points touches only the
entities of those points: the others keep their state, and the entry is not reloaded.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from functools import lru_cache
import sys
from typing import Any, Final

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
    CONF_READ_ONLY,
    CONF_ROLE,
    CONF_SCALE,
    CONF_STEP,
    PULSE_MAX,
    PULSE_MIN,
    SUBENTRY_DEVICE,
)
from ..plc import PlcAddressError, PlcClient, Point, ValueKind
from .conversion import Conversion, Pairs, conversion_of, stored_pairs
from .device_classes import class_errors
from .kinds import CONTROLS, KINDS, NUMERIC, POINT_PLATFORMS
from .point_kinds import kind_data
from .poll_classes import NORMAL, POLL_CLASSES, has_poll_class, poll_data

type Reader = Callable[[Any], Any]
"""Reads one stored value as its attribute's type; raises TypeError or ValueError if it cannot."""


def _text(value: Any) -> str:
    """Return a stored text."""
    return value if isinstance(value, str) else str(value)


def _text_or_none(value: Any) -> str | None:
    """Return a stored text that may be null."""
    return None if value is None else _text(value)


def _number(value: Any) -> float:
    """Return a stored number as stored (an int stays one: the round trip gives it back)."""
    if isinstance(value, int | float) and not isinstance(value, bool):
        return value
    return float(value)


def _number_or_none(value: Any) -> float | None:
    """Return a stored number that may be null."""
    return None if value is None else _number(value)


def _whole_or_none(value: Any) -> int | None:
    """Return a stored whole number that may be null."""
    if value is None or (isinstance(value, int) and not isinstance(value, bool)):
        return value
    return int(value)


def _poll(value: Any) -> str:
    """Return a stored poll class (normal where it names none)."""
    return value if value in POLL_CLASSES else NORMAL


FIELDS: Final[dict[str, tuple[Reader, Any]]] = {
    "name": (_text, ""),
    "platform": (_text, ""),
    "address": (_text, ""),
    "data_type": (_text, ""),
    "scale": (_number, 1.0),
    "offset": (_number, 0.0),
    "read_only": (bool, False),
    "min": (_number_or_none, None),
    "max": (_number_or_none, None),
    "step": (_number_or_none, None),
    "value_map": (_text_or_none, None),
    "raw_min": (_number_or_none, None),
    "raw_max": (_number_or_none, None),
    "shown_min": (_number_or_none, None),
    "shown_max": (_number_or_none, None),
    "precision": (_whole_or_none, None),
    "invert": (bool, False),
    "on_value": (_number_or_none, None),
    "off_value": (_number_or_none, None),
    "pulse": (_number_or_none, None),
    "bits": (_text_or_none, None),
    "role": (_text_or_none, None),
    "as_text": (bool, False),
    "entity": (_text_or_none, None),
    "poll": (_poll, NORMAL),
    "travel_time": (_number_or_none, None),
    "supervision": (_number_or_none, None),
    "availability": (_text_or_none, None),
    "device_class": (_text_or_none, None),
    "unit_of_measurement": (_text_or_none, None),
    "state_class": (_text_or_none, None),
}
"""Every key a stored point may have (each an attribute of PointConfig), its reader and the
value of a point that stores none."""
_IN_POINT: Final = ("address", "data_type")
"""Keys kept in the shared Point, not as attributes of their own."""


@lru_cache(maxsize=1024)
def _shape(keys: tuple[str, ...]) -> tuple[str, ...]:
    """Return one tuple for the stored keys of every point of the same shape."""
    return keys


@dataclass(frozen=True, slots=True, init=False, eq=False)
class PointConfig:
    """One configured point: where it is stored and what the user set for it, typed.

    Read once from its stored mapping; `stored()` gives that mapping back as it was: the keys
    it had in their order, and a value its attribute cannot hold as stored (a text where a
    number belongs, a key no point knows) from `extra`. A key the point does not store reads as
    its default in FIELDS. Equal stored mappings give equal points.
    """

    point_id: str
    subentry_id: str
    point: Point
    """The PLC address and data type the point reads (one object for equal points)."""
    name: str
    platform: str
    scale: float
    offset: float
    read_only: bool
    """True when Home Assistant must never write the point."""
    min: float | None
    max: float | None
    step: float | None
    value_map: str | None
    raw_min: float | None
    raw_max: float | None
    shown_min: float | None
    shown_max: float | None
    precision: int | None
    invert: bool
    on_value: float | None
    off_value: float | None
    pulse: float | None
    bits: str | None
    role: str | None
    as_text: bool
    entity: str | None
    poll: str
    """The point's poll class: fast, normal or slow (normal where it names none)."""
    travel_time: float | None
    supervision: float | None
    availability: str | None
    """The availability policy it stores (model/availability.py), None for its machine's."""
    device_class: str | None
    unit_of_measurement: str | None
    state_class: str | None
    bit_pairs: Pairs
    """The named bits of an alarm word, parsed once (one tuple for equal lists)."""
    conversion: Conversion
    """Its conversions (one object for equal ones); `conversion.value_map` the parsed map."""
    keys: tuple[str, ...]
    extra: Mapping[str, Any] | None

    def __init__(self, point_id: str, subentry_id: str, data: Mapping[str, Any]) -> None:
        """Read a stored point (the data of a point id of a machine subentry)."""
        values: dict[str, Any] = {"point_id": point_id, "subentry_id": subentry_id}
        extra: dict[str, Any] = {}
        for key, (reader, default) in FIELDS.items():
            if key not in data:
                values[key] = default
                continue
            raw = data[key]
            try:
                values[key] = reader(raw)
            except (TypeError, ValueError):
                values[key] = default
            if type(values[key]) is not type(raw) or values[key] != raw:
                extra[key] = raw
        extra |= {key: value for key, value in data.items() if key not in FIELDS}
        values["point"] = shared_point(values.pop("address"), values.pop("data_type"))
        values["bit_pairs"] = stored_pairs(values, "bits")
        values["conversion"] = conversion_of(values)
        values["keys"] = _shape(tuple(data))
        values["extra"] = extra or None
        for key, value in values.items():
            object.__setattr__(self, key, value)

    def stored(self) -> dict[str, Any]:
        """Return the point as it was stored (what Home Assistant keeps, exports show)."""
        extra = self.extra or {}
        return {key: extra[key] if key in extra else self._value(key) for key in self.keys}

    def _value(self, key: str) -> Any:
        """Return the stored value of one key the point knows."""
        if key in _IN_POINT:
            return getattr(self.point, key)
        return getattr(self, key)

    def __eq__(self, other: object) -> bool:
        """Equal where stored at the same place with equal data."""
        if not isinstance(other, PointConfig):
            return NotImplemented
        return (self.point_id, self.subentry_id, self.stored()) == (
            other.point_id,
            other.subentry_id,
            other.stored(),
        )

    def __hash__(self) -> int:
        """Hash by where the point is stored."""
        return hash((self.point_id, self.subentry_id))

    @property
    def address(self) -> str:
        """The PLC address the point reads."""
        return self.point.address

    @property
    def data_type(self) -> str:
        """The vendor's data type the point reads."""
        return self.point.data_type

    @property
    def platforms(self) -> tuple[str, ...]:
        """Every platform with entities of the point (an alarm word: also one per named bit)."""
        kind = KINDS.get(self.platform)
        return (self.platform, *(kind.also_shown_on if kind else ()))

    @property
    def pulse_seconds(self) -> float:
        """The point's pulse in seconds, kept within 0.1-60; 0 for a single write."""
        pulse = self.pulse or 0.0
        return min(max(pulse, PULSE_MIN), PULSE_MAX) if pulse else 0.0


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
