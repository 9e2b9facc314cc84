"""Numbers: writable numeric points, scaled, within the range the user set."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import timedelta

from homeassistant.components.number import (
    NumberDeviceClass,
    NumberEntity,
    NumberEntityDescription,
    NumberMode,
)
from homeassistant.const import UnitOfTime
from homeassistant.core import HomeAssistant
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from .coordinator import PlcBridgeConfigEntry
from .entity import PlcPointDescription, PlcPointEntity, device_class, point_fields
from .model.duration_units import UNITS, duration_unit, in_unit, of_unit
from .model.points import PointConfig
from .plc import ValueKind

PARALLEL_UPDATES = 1
MILLISECOND = timedelta(milliseconds=1)

# Without a range from the user, allow what a 32-bit point can hold; the vendor's check
# refuses a value that does not fit the point's own type before anything is sent.
DEFAULT_MIN = -2_147_483_648.0
DEFAULT_MAX = 4_294_967_295.0


@dataclass(frozen=True, kw_only=True)
class PlcNumberDescription(NumberEntityDescription, PlcPointDescription):
    """A point shown as a number."""


def point_number(entry: PlcBridgeConfigEntry, config: PointConfig) -> PlcNumber:
    """Return the number of a point; the step defaults to one raw count for integers."""
    fields = point_fields(entry, config)
    precision = fields["conversion"].precision
    duration = fields["kind"] is ValueKind.DURATION  # seconds or its time unit; the PLC checks
    unit = duration_unit(config.unit_of_measurement) if duration else config.unit_of_measurement
    step = config.step or (
        10.0**-precision
        if precision is not None
        else abs(fields["scale"])
        if fields["kind"] is ValueKind.INTEGER
        else in_unit(MILLISECOND, duration_unit(config.unit_of_measurement))
        if duration
        else 0.001
    )
    low, high = fields["conversion"].bounds or (DEFAULT_MIN, DEFAULT_MAX)
    description = PlcNumberDescription(
        **fields,
        device_class=NumberDeviceClass.DURATION
        if duration
        else device_class(config, NumberDeviceClass),
        native_unit_of_measurement=unit,
        native_min_value=float(low if config.min is None else config.min),
        native_max_value=float(high if config.max is None else config.max),
        native_step=float(step),
        # A box, not a slider: dragging would write every value it passes to the machine.
        mode=NumberMode.BOX,
    )
    return PlcNumber(entry, config, description)


async def async_setup_entry(
    hass: HomeAssistant,
    entry: PlcBridgeConfigEntry,
    async_add_entities: AddConfigEntryEntitiesCallback,
) -> None:
    """Add a number for each number point."""
    entry.runtime_data.points.async_setup_platform("number", point_number, async_add_entities)


class PlcNumber(PlcPointEntity, NumberEntity):
    """A numeric point the user can set; Home Assistant checks the range before it is written."""

    entity_description: PlcNumberDescription

    @property
    def native_value(self) -> float | None:
        """Return the scaled value."""
        value = self.entity_description.value_fn(self.raw_value)
        unit = self.entity_description.native_unit_of_measurement
        if isinstance(value, timedelta):
            return in_unit(value, unit or UnitOfTime.SECONDS)
        return value if isinstance(value, int | float) else None

    async def async_set_native_value(self, value: float) -> None:
        """Write the value with the scaling inverted (a duration in its unit)."""
        description = self.entity_description
        unit = description.native_unit_of_measurement
        if description.kind is ValueKind.DURATION and unit in UNITS:
            await self.async_write(of_unit(value, unit))
        else:
            await self.async_write(description.raw_fn(value))
