"""Every entity kind described once: its platform, its roles and what each role needs.

A kind of one address (a sensor, a switch, a select, ...) says which values it can show, whether
it writes its point and what its form asks besides the point form's own fields. A kind of
several addresses (a cover, a climate, ...) lists its roles: each is checked and stored as a
kind of one address, takes the values that kind takes, may bound the labels of its value map,
belongs to a section of the entity's form and enables entity features while it is written. The
point forms, the composite flow, the point tables, the pasted file and the entities read these
descriptions; the dicts the rest of the code looks up are derived from them below.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, replace
from enum import IntFlag, StrEnum
from typing import Any, Final

from homeassistant.components.binary_sensor import (  # type: ignore[attr-defined]
    BinarySensorDeviceClass,
)
from homeassistant.components.climate.const import ClimateEntityFeature, HVACAction, HVACMode
from homeassistant.components.cover import CoverDeviceClass, CoverEntityFeature
from homeassistant.components.fan import FanEntityFeature  # type: ignore[attr-defined]
from homeassistant.components.number import NumberDeviceClass
from homeassistant.components.number.const import DEVICE_CLASS_UNITS as NUMBER_UNITS
from homeassistant.components.sensor import SensorDeviceClass
from homeassistant.components.sensor.const import DEVICE_CLASS_UNITS as SENSOR_UNITS
from homeassistant.components.switch import SwitchDeviceClass  # type: ignore[attr-defined]
from homeassistant.components.valve import (  # type: ignore[attr-defined]
    ValveDeviceClass,
    ValveEntityFeature,
)
from homeassistant.components.water_heater import (  # type: ignore[attr-defined]
    STATE_ECO,
    STATE_ELECTRIC,
    STATE_GAS,
    STATE_HEAT_PUMP,
    STATE_HIGH_DEMAND,
    STATE_PERFORMANCE,
    WaterHeaterEntityFeature,
)
from homeassistant.const import CONF_UNIT_OF_MEASUREMENT, STATE_OFF, Platform

from ..plc import ValueKind

CONF_TRAVEL_TIME: Final = "travel_time"
"""Part data of a cover or valve: seconds a full travel takes (absent: none); every part has it."""
CONF_SUPERVISION: Final = "supervision"
"""Part data: seconds the state has to follow a command (absent: none); every part has it."""

NUMERIC = frozenset({ValueKind.INTEGER, ValueKind.FLOAT})
ON_OFF = frozenset({ValueKind.BOOL, ValueKind.INTEGER})
"""A point that is on or off: a bit, or an integer whose codes say on and off (1 and 0)."""
COVER_STATES = ("open", "closed", "opening", "closing")
"""The labels a cover's or valve's status map may use."""
WATER_HEATER_STATES = (
    STATE_ECO,
    STATE_ELECTRIC,
    STATE_PERFORMANCE,
    STATE_HIGH_DEMAND,
    STATE_HEAT_PUMP,
    STATE_GAS,
    STATE_OFF,
)
"""The labels a water heater's operation mode map may use: Home Assistant's operation modes."""


@dataclass(frozen=True, slots=True, kw_only=True)
class Role:
    """One part of a kind of several addresses, and what it needs."""

    key: str
    """The role's name as stored in a part's `role` and named in tables and files."""
    checked_as: str
    """The kind of one address the part is checked, stored and shown on its form as."""
    section: str
    """The section of the entity's form the role belongs to (commands, position, modes, ...)."""
    labels: tuple[str, ...] = ()
    """The only labels its value map may use (Home Assistant's states); a map is then required."""
    shows: bool = False
    """One of the roles of which an entity needs at least one to show anything."""
    invertible: bool = False
    """A position counted the other way may be inverted (a part on or off always may)."""
    features: tuple[str, ...] = ()
    """The entity features (flag names) the part enables while Home Assistant writes it."""
    asks: tuple[str, ...] = ()
    """The settings of its own the entity's page asks beside its address (`<role>_<setting>`)."""
    shares: tuple[str, ...] = ()
    """The settings it takes from fields its section asks once for all its roles (a pulse, a
    temperature's unit and scale, a position's raw range)."""
    percent: bool = False
    """It reads or sets 0-100 %: a raw range given maps onto 0-100."""

    @property
    def translation_key(self) -> str:
        """The key of the role's label and help in the forms (its address field)."""
        return self.key

    @property
    def single(self) -> Kind:
        """The kind of one address the part is checked as."""
        return KINDS[self.checked_as]

    @property
    def value_kinds(self) -> frozenset[ValueKind] | None:
        """The kinds of value (data types) the role accepts; None: any."""
        return self.single.value_kinds

    @property
    def written(self) -> bool:
        """True for a role Home Assistant writes: never read only (a command, a set point)."""
        return self.single.writes


@dataclass(frozen=True, slots=True, kw_only=True)
class Kind:
    """One entity kind: its platform, its point's or parts' needs, the form fields it adds."""

    key: str
    """The platform's name, stored in every point's `platform`."""
    single: bool = False
    """A point of its own can be this kind (the point form offers it)."""
    value_kinds: frozenset[ValueKind] | None = None
    """The kinds of value a point of its own can show (None: any), and the error if not one."""
    kind_error: str = ""
    writes: bool = False
    """A point of its own (or a part checked as it) is written: it needs a writable address."""
    polled: bool = True
    """Its point shows a value, so it is read and has a poll class (not a button)."""
    also_shown_on: tuple[str, ...] = ()
    """Platforms a point of its own shows on besides its own (an alarm word: a sensor per bit)."""
    device_class: type[StrEnum] | None = None
    """The device classes it can carry (a sensor's are narrowed by its value)."""
    units: Mapping[Any, Any] | None = None
    """The units Home Assistant allows per device class, where it checks them."""
    scaled: bool = False
    """Its point shows a number: scale, offset and a unit apply."""
    measures: bool = False
    """It shows a measurement: a state class, and only the device classes its value fits."""
    bounded: bool = False
    """It is set within a minimum, a maximum and a step."""
    value_map: str = ""
    """Whether its form asks a value map: "required", "optional" (integer points) or not."""
    bits: bool = False
    linear: bool = False
    invert: bool = False
    codes: bool = False
    pulse: bool = False
    as_text: bool = False
    """The fields its form adds: named bits, a linear range, invert, on/off codes, a pulse, a
    duration shown as text."""
    roles: tuple[Role, ...] = ()
    """The parts of an entity of several addresses, in the order the forms list them."""
    parts_only: bool = False
    """Every point of the kind is a part; else (a switch) only one that names a role."""
    entity_time: str = ""
    """The entity's time setting its parts share: travel time or supervision time (or none)."""
    feature: type[IntFlag] | None = None
    always_features: tuple[str, ...] = ()
    """The entity's feature flags, and those it always has."""
    open_sections: tuple[str, ...] = ()
    """The sections of the entity's page shown open (the others start folded)."""

    @property
    def platform(self) -> Platform:
        """The Home Assistant platform that shows the kind."""
        return Platform(self.key)

    @property
    def role_keys(self) -> tuple[str, ...]:
        """The names of its roles, in form order."""
        return tuple(role.key for role in self.roles)

    def role(self, key: str) -> Role | None:
        """Return the role of this name, None if the kind has none so named."""
        return next((role for role in self.roles if role.key == key), None)

    @property
    def needs_one_of(self) -> tuple[str, ...]:
        """The roles of which an entity needs at least one to show anything."""
        return tuple(role.key for role in self.roles if role.shows)

    @property
    def sections(self) -> dict[str, tuple[Role, ...]]:
        """Its roles by the section of its page they belong to, in form order."""
        found: dict[str, tuple[Role, ...]] = {}
        for role in self.roles:
            found[role.section] = (*found.get(role.section, ()), role)
        return found

    def shared(self, section: str) -> tuple[str, ...]:
        """The settings a section of its page asks once for all its roles, in form order."""
        return tuple(dict.fromkeys(s for role in self.sections[section] for s in role.shares))

    def own_class(self, given: Any) -> str:
        """Return `given` where it is one of the kind's own device classes (a shutter), else ""."""
        if self.device_class is None or not given:
            return ""
        return str(given) if str(given) in set(self.device_class) else ""

    def features(self, written: Iterable[str]) -> int:
        """Return the feature flags an entity has with these roles written (its enum's value)."""
        if self.feature is None:
            return 0
        names = set(self.always_features)
        for key in written:
            if (role := self.role(key)) is not None:
                names.update(role.features)
        flags = self.feature(0)
        for name in names:
            flags |= self.feature[name]
        return flags


def _role(key: str, checked_as: str, section: str, **more: Any) -> Role:
    """Return a role (shorter to read in the tables below)."""
    return Role(key=key, checked_as=checked_as, section=section, **more)


_MOVES = ("OPEN", "CLOSE", "SET_POSITION")
_PULSED = ("pulse",)
"""What commands share on the page: one pulse length (empty: the command is held)."""
_RANGED = ("invert", "raw_min", "raw_max")
"""What the read and set 0-100 % values of one section share: the direction and raw range."""
_MAPPED = ("value_map",)
_INVERTED = ("invert",)


def _percent(key: str, checked_as: str, section: str, **more: Any) -> Role:
    """Return a position or tilt role: 0-100 %, with the direction and raw range of its section."""
    return _role(key, checked_as, section, invertible=True, shares=_RANGED, percent=True, **more)


COVER = Kind(
    key="cover",
    device_class=CoverDeviceClass,
    parts_only=True,
    entity_time=CONF_TRAVEL_TIME,
    feature=CoverEntityFeature,
    open_sections=("commands", "limits"),
    roles=(
        _percent("position", "sensor", "position", shows=True, features=_MOVES),
        _percent("set_position", "number", "position", shows=True, features=_MOVES),
        _role("open", "button", "commands", shows=True, features=("OPEN",), shares=_PULSED),
        _role("close", "button", "commands", shows=True, features=("CLOSE",), shares=_PULSED),
        _role("stop", "button", "commands", features=("STOP",), shares=_PULSED),
        _role("open_limit", "binary_sensor", "limits", shows=True, asks=_INVERTED),
        _role("closed_limit", "binary_sensor", "limits", shows=True, asks=_INVERTED),
        _role("status", "sensor", "limits", shows=True, labels=COVER_STATES, asks=_MAPPED),
        _percent("tilt_position", "sensor", "tilt", features=("SET_TILT_POSITION",)),
        _percent("set_tilt_position", "number", "tilt", features=("SET_TILT_POSITION",)),
        _role(
            "step",
            "button",
            "commands",
            shows=True,
            features=("OPEN", "CLOSE", "STOP"),
            shares=_PULSED,
        ),
    ),
)
VALVE = replace(
    COVER,
    key="valve",
    device_class=ValveDeviceClass,
    feature=ValveEntityFeature,
    roles=tuple(role for role in COVER.roles if role.section != "tilt" and role.key != "step"),
)
"""A valve is a cover without tilt and step relay."""
_ON_OFF_ROLES = (
    _role("state", "binary_sensor", "on_off", asks=_INVERTED),
    _role("command", "button", "on_off", shows=True, shares=_PULSED),
)
_TEMPERATURE = (CONF_UNIT_OF_MEASUREMENT, "scale", "offset")
"""What a temperature read and one set share on the page: their unit and scaling."""
_TEMPERATURES = (
    _role("current_temperature", "sensor", "temperatures", shows=True, shares=_TEMPERATURE),
    _role(
        "target_temperature",
        "number",
        "temperatures",
        shows=True,
        features=("TARGET_TEMPERATURE",),
        shares=(*_TEMPERATURE, "min", "max", "step"),
    ),
)
"""The temperatures of a climate entity and of a water heater (their feature flags share names)."""
CLIMATE = Kind(
    key="climate",
    parts_only=True,
    entity_time=CONF_SUPERVISION,
    feature=ClimateEntityFeature,
    open_sections=("temperatures", "modes"),
    roles=(
        *_TEMPERATURES,
        _role(
            "hvac_mode",
            "select",
            "modes",
            shows=True,
            labels=tuple(map(str, HVACMode)),
            asks=_MAPPED,
        ),
        _role("hvac_action", "sensor", "action", labels=tuple(map(str, HVACAction)), asks=_MAPPED),
        _role(
            "on_off",
            "switch",
            "on_off",
            shows=True,
            features=("TURN_ON", "TURN_OFF"),
            asks=_INVERTED,
        ),
        _role("preset", "select", "presets", features=("PRESET_MODE",), asks=_MAPPED),
    ),
)
KINDS_IN_ORDER: tuple[Kind, ...] = (
    Kind(
        key="sensor",
        single=True,
        scaled=True,
        measures=True,
        device_class=SensorDeviceClass,
        units=SENSOR_UNITS,
        value_map="optional",
        linear=True,
        as_text=True,
    ),
    Kind(
        key="binary_sensor",
        single=True,
        value_kinds=ON_OFF,
        kind_error="needs_bool",
        device_class=BinarySensorDeviceClass,
        invert=True,
        codes=True,
    ),
    Kind(
        key="switch",
        single=True,
        value_kinds=ON_OFF,
        kind_error="needs_bool",
        writes=True,
        device_class=SwitchDeviceClass,
        invert=True,
        codes=True,
        roles=_ON_OFF_ROLES,
        entity_time=CONF_SUPERVISION,
        open_sections=("on_off",),
    ),
    Kind(
        key="number",
        single=True,
        scaled=True,
        bounded=True,
        value_kinds=NUMERIC | {ValueKind.DURATION},
        kind_error="needs_number",
        writes=True,
        device_class=NumberDeviceClass,
        units=NUMBER_UNITS,
        linear=True,
    ),
    Kind(
        key="datetime",
        single=True,
        value_kinds=frozenset({ValueKind.DATETIME}),
        kind_error="needs_datetime",
        writes=True,
    ),
    Kind(
        key="text",
        single=True,
        value_kinds=frozenset({ValueKind.TEXT, ValueKind.DURATION}),  # hh:mm:ss.zzz
        kind_error="needs_text",
        writes=True,
    ),
    Kind(
        key="select",
        single=True,
        value_kinds=frozenset({ValueKind.INTEGER}),
        kind_error="needs_integer",
        writes=True,
        value_map="required",
    ),
    Kind(
        key="button",
        single=True,
        value_kinds=ON_OFF,
        kind_error="needs_bool_or_integer",
        writes=True,
        polled=False,
        codes=True,
        pulse=True,
    ),
    Kind(
        key="event",
        single=True,
        value_kinds=frozenset({ValueKind.INTEGER}),
        kind_error="needs_integer",
        also_shown_on=("binary_sensor",),
        bits=True,
    ),
    COVER,
    VALVE,
    CLIMATE,
    Kind(
        key="fan",
        parts_only=True,
        entity_time=CONF_SUPERVISION,
        feature=FanEntityFeature,
        always_features=("TURN_ON", "TURN_OFF"),
        open_sections=("on_off", "speed"),
        roles=(
            *_ON_OFF_ROLES,
            _role(
                "percentage",
                "number",
                "speed",
                shows=True,
                features=("SET_SPEED",),
                shares=_RANGED[1:],
                percent=True,
            ),
            _role("preset", "select", "presets", features=("PRESET_MODE",), asks=_MAPPED),
        ),
    ),
    Kind(
        key="light",
        parts_only=True,
        entity_time=CONF_SUPERVISION,
        open_sections=("on_off", "brightness"),
        roles=(
            *_ON_OFF_ROLES,
            _role(
                "brightness",
                "number",
                "brightness",
                shows=True,
                shares=_RANGED[1:],
                percent=True,
            ),
        ),
    ),
    Kind(
        key="water_heater",
        parts_only=True,
        feature=WaterHeaterEntityFeature,
        open_sections=("temperatures", "modes"),
        roles=(
            *_TEMPERATURES,
            _role(
                "operation_mode",
                "select",
                "modes",
                shows=True,
                labels=WATER_HEATER_STATES,
                features=("OPERATION_MODE",),
                asks=_MAPPED,
            ),
            _role("on_off", "switch", "on_off", shows=True, features=("ON_OFF",), asks=_INVERTED),
        ),
    ),
)
"""Every kind: those of one address in the point form's order, then those of several."""

KINDS: dict[str, Kind] = {kind.key: kind for kind in KINDS_IN_ORDER}
PLATFORMS: Final = sorted((kind.platform for kind in KINDS_IN_ORDER), key=str)
"""The platforms the integration sets up, and each one's module: every kind's."""
POINT_PLATFORMS: Final = tuple(kind.key for kind in KINDS_IN_ORDER if kind.single)
"""The kinds a point of its own can be, in the point form's order."""
COMPOSITE_PLATFORMS: Final = tuple(
    kind.key for kind in sorted(KINDS_IN_ORDER, key=lambda kind: not kind.parts_only) if kind.roles
)
"""The kinds of several addresses in the composite form's order (a switch, also single, last)."""
CONTROLS: Final = frozenset(kind.key for kind in KINDS_IN_ORDER if kind.single and kind.writes)
"""Kinds that write their point: a point only gets one where it asks for it."""
