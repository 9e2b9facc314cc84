"""Sensors: points shown as values, and the status the PLC reports beside them."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from datetime import datetime, timedelta
from typing import Any

from homeassistant.components.sensor import (
    SensorDeviceClass,
    SensorEntity,
    SensorEntityDescription,
    SensorStateClass,
)
from homeassistant.const import EntityCategory, UnitOfTime
from homeassistant.core import HomeAssistant
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback
from homeassistant.util import dt as dt_util

from .const import LOGGER
from .coordinator import PlcBridgeConfigEntry
from .entity import (
    PlcEntity,
    PlcPointDescription,
    PlcPointEntity,
    async_remove_entity,
    device_class,
    point_fields,
)
from .link import link_sensors
from .model.conversion import check_unmapped, labels
from .model.duration_units import duration_unit, in_unit
from .model.points import PointConfig
from .plc import PlcStatus, ValueKind
from .plc.durations import clock_text

PARALLEL_UPDATES = 0

OPERATING_MODES = ["run", "stop", "startup", "halt", "hold", "error"]
"""The operating modes PLCs report, lower case (anything else shows as unknown)."""
KNOWN_EXTRA = (
    "cycle_time",
    "cpu_load",
    "last_error",
    "program",
    "program_stamp",
    "project_crc",
    "groups_registered_again",
)
"""PlcStatus.extra keys with translated names; other keys are shown under their own name."""
SHOWN_EXTRA = ("program", "program_compiled", "project_crc")
"""Extra keys whose sensors are enabled by default (the others are there, disabled)."""
NUMERIC = (ValueKind.INTEGER, ValueKind.FLOAT, ValueKind.BOOL)


@dataclass(frozen=True, kw_only=True)
class PlcSensorDescription(SensorEntityDescription, PlcPointDescription):
    """A point shown as a sensor."""


@dataclass(frozen=True, kw_only=True)
class PlcStatusDescription(SensorEntityDescription):
    """A status field of the PLC shown as a diagnostic sensor."""

    value_fn: Callable[[PlcStatus], str | datetime | None]


def operating_mode(status: PlcStatus) -> str | None:
    """Return the operating mode as an option of the enum sensor."""
    mode = (status.mode or "").strip().lower()
    return mode if mode in OPERATING_MODES else None


STATUS = (
    PlcStatusDescription(
        key="operating_mode",
        translation_key="operating_mode",
        device_class=SensorDeviceClass.ENUM,
        options=OPERATING_MODES,
        value_fn=operating_mode,
    ),
    PlcStatusDescription(
        key="system_status",
        translation_key="system_status",
        entity_registry_enabled_default=False,
        value_fn=lambda status: status.system,
    ),
    PlcStatusDescription(
        key="force_status",
        translation_key="force_status",
        entity_registry_enabled_default=False,
        value_fn=lambda status: status.force,
    ),
)
CLOCK = PlcStatusDescription(
    key="plc_clock",
    translation_key="plc_clock",
    device_class=SensorDeviceClass.TIMESTAMP,
    # Its state changes at every clock read: off by default, the drift below says enough.
    entity_registry_enabled_default=False,
    value_fn=lambda status: status.clock,
)
"""The PLC clock, read only: for PLCs whose clock cannot be set (else it is a datetime)."""
DRIFT = SensorEntityDescription(
    key="clock_drift",
    translation_key="clock_drift",
    device_class=SensorDeviceClass.DURATION,
    native_unit_of_measurement=UnitOfTime.SECONDS,
    suggested_display_precision=0,  # whole seconds: "-133 s", not "-133.00 s"
    state_class=SensorStateClass.MEASUREMENT,
    entity_category=EntityCategory.DIAGNOSTIC,
)
DRIFT_STEP = 2
"""Seconds the drift must move before it is shown anew: PLC clocks tick in whole seconds."""
COMPILED = PlcStatusDescription(
    key="extra_program_compiled",
    translation_key="program_compiled",
    device_class=SensorDeviceClass.TIMESTAMP,
    value_fn=lambda status: timestamp(status.extra.get("program_compiled")),
)
REPORTED: dict[str, Callable[[PlcStatus], bool]] = {
    "operating_mode": lambda status: status.mode is not None,
    "system_status": lambda status: status.system is not None,
    "force_status": lambda status: status.force is not None,
}


def timestamp(text: str | None) -> datetime | None:
    """Return an ISO 8601 time with its offset (as vendors report it in extra), else None."""
    try:
        moment = datetime.fromisoformat(text) if text else None
    except ValueError:
        return None
    return moment if moment is not None and moment.tzinfo is not None else None


def extra_description(key: str) -> PlcStatusDescription:
    """Return the description of a vendor-specific status field."""
    if key == "program_compiled":
        return COMPILED
    known = key in KNOWN_EXTRA
    return PlcStatusDescription(
        key=f"extra_{key}",
        translation_key=key if known else None,
        name=None if known else key,
        entity_registry_enabled_default=key in SHOWN_EXTRA,
        value_fn=lambda status: status.extra.get(key),
    )


def point_sensor(entry: PlcBridgeConfigEntry, config: PointConfig) -> PlcPointSensor:
    """Return the sensor of a point: numbers keep unit and classes, other values show as text."""
    fields = point_fields(entry, config)
    extra: dict[str, Any] = {}
    if options := labels(fields["conversion"].value_map):
        description = PlcSensorDescription(
            **fields, device_class=SensorDeviceClass.ENUM, options=options
        )
        return PlcEnumSensor(entry, config, description)
    if fields["kind"] in NUMERIC or fields["kind"] is None:
        extra = {
            "native_unit_of_measurement": config.unit_of_measurement,
            "device_class": device_class(config, SensorDeviceClass),
            "state_class": config.state_class,
            "suggested_display_precision": fields["conversion"].precision,
        }
        if extra["state_class"]:
            extra["state_class"] = SensorStateClass(extra["state_class"])
    elif fields["kind"] is ValueKind.DATETIME:
        extra = {"device_class": SensorDeviceClass.TIMESTAMP}
    elif fields["kind"] is ValueKind.DURATION and not config.as_text:
        extra = {  # seconds, or the time unit the point names; no unit: clock text
            "device_class": SensorDeviceClass.DURATION,
            "native_unit_of_measurement": duration_unit(config.unit_of_measurement),
            "state_class": config.state_class,
            "suggested_display_precision": fields["conversion"].precision,
        }
    return PlcPointSensor(entry, config, PlcSensorDescription(**fields, **extra))


async def async_setup_entry(
    hass: HomeAssistant,
    entry: PlcBridgeConfigEntry,
    async_add_entities: AddConfigEntryEntitiesCallback,
) -> None:
    """Add the point sensors, a diagnostic sensor per status field reported, and the link's."""
    status = entry.runtime_data.coordinator.data.status
    descriptions = [d for d in STATUS if REPORTED[d.key](status)]
    settable = entry.runtime_data.client.can_set_clock
    if status.clock is not None and not settable:
        descriptions.append(CLOCK)
    elif settable:  # a clock variable was named since: the read-only clock goes
        async_remove_entity(hass, entry, "sensor", CLOCK.key)
    descriptions += [extra_description(key) for key in sorted(status.extra)]
    entities: list[SensorEntity] = [PlcStatusSensor(entry, d) for d in descriptions]
    if status.clock is not None:
        entities.append(PlcClockDrift(entry))
    entities += link_sensors(entry)
    async_add_entities(entities)
    entry.runtime_data.points.async_setup_platform("sensor", point_sensor, async_add_entities)


class PlcPointSensor(PlcPointEntity, SensorEntity):
    """A point's value."""

    entity_description: PlcSensorDescription

    @property
    def native_value(self) -> Any:
        """Return the scaled value (text for strings and raw bytes)."""
        value = self.entity_description.value_fn(self.raw_value)
        if isinstance(value, timedelta):
            unit = self.entity_description.native_unit_of_measurement
            return clock_text(value) if unit is None else in_unit(value, unit)
        return int(value) if isinstance(value, bool) else value


class PlcEnumSensor(PlcPointSensor):
    """A read-only point with a value map: the label of its value, unknown outside the map."""

    def __init__(
        self, entry: PlcBridgeConfigEntry, config: PointConfig, description: PlcSensorDescription
    ) -> None:
        """Bind the sensor to its point and note raw values outside the map."""
        super().__init__(entry, config, description)
        self._label = config.name
        self._unmapped = False

    @property
    def native_value(self) -> str | None:
        """Return the label of the point's value."""
        return self.entity_description.convert.label(self.raw_value)

    def observed(self) -> Any:
        """The point's value as read in the last poll (a value outside the map logged once)."""
        self._unmapped = check_unmapped(
            LOGGER, self._label, self.entity_description.convert, self.raw_value, self._unmapped
        )
        return self.raw_value


class PlcStatusSensor(PlcEntity, SensorEntity):
    """A status field of the PLC, read with every poll."""

    entity_description: PlcStatusDescription
    _attr_entity_category = EntityCategory.DIAGNOSTIC

    def __init__(self, entry: PlcBridgeConfigEntry, description: PlcStatusDescription) -> None:
        """Bind the sensor to its status field."""
        super().__init__(entry, description.key)
        self.entity_description = description

    @property
    def native_value(self) -> str | datetime | None:
        """Return the field as the PLC reported it in the last poll."""
        return self.entity_description.value_fn(self.coordinator.data.status)

    def observed(self) -> Any:
        """The status field of the last poll."""
        return self.native_value


class PlcClockDrift(PlcEntity, SensorEntity):
    """How far the PLC clock is ahead of Home Assistant's, in whole seconds.

    Taken at each fresh clock read (vendors read the clock at their own pace) and shown anew
    only when it moves by DRIFT_STEP or more: a PLC clock that keeps time writes no state.
    """

    entity_description = DRIFT

    def __init__(self, entry: PlcBridgeConfigEntry) -> None:
        """Bind the sensor to the PLC's clock."""
        super().__init__(entry, DRIFT.key)
        self._clock: datetime | None = None
        self._drift: int | None = None
        self._measure()

    def _measure(self) -> None:
        """Take the drift from a clock read newer than the last one."""
        clock = self.coordinator.data.status.clock
        if clock is None or clock == self._clock:
            return
        self._clock = clock
        drift = round((clock - dt_util.now()).total_seconds())
        if self._drift is None or abs(drift - self._drift) >= DRIFT_STEP:
            self._drift = drift

    @property
    def native_value(self) -> int | None:
        """Return the drift shown."""
        return self._drift

    def observed(self) -> Any:
        """The drift shown, updated from the last poll."""
        self._measure()
        return self._drift
