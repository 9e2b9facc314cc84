"""Binary sensors: BOOL points, shown on or off."""

from __future__ import annotations

from dataclasses import dataclass

from homeassistant.components.binary_sensor import (  # type: ignore[attr-defined]
    BinarySensorDeviceClass,
    BinarySensorEntity,
    BinarySensorEntityDescription,
)
from homeassistant.core import HomeAssistant
from homeassistant.helpers.entity import Entity
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from .alarm import bit_sensors
from .coordinator import PlcBridgeConfigEntry
from .entity import (
    PlcPointDescription,
    PlcPointEntity,
    device_class,
    point_fields,
)
from .link import PlcConnectivity
from .points import PointConfig

PARALLEL_UPDATES = 0


@dataclass(frozen=True, kw_only=True)
class PlcBinarySensorDescription(BinarySensorEntityDescription, PlcPointDescription):
    """A point shown as a binary sensor."""


def point_binary_sensor(
    entry: PlcBridgeConfigEntry, config: PointConfig
) -> PlcBinarySensor | list[Entity]:
    """Return the binary sensor of a point; an alarm word's: one per named bit."""
    if config.platform == "event":
        return bit_sensors(entry, config)
    description = PlcBinarySensorDescription(
        **point_fields(entry, config),
        device_class=device_class(config, BinarySensorDeviceClass),
    )
    return PlcBinarySensor(entry, config, description)


async def async_setup_entry(
    hass: HomeAssistant,
    entry: PlcBridgeConfigEntry,
    async_add_entities: AddConfigEntryEntitiesCallback,
) -> None:
    """Add the PLC's connectivity sensor, and a binary sensor for each binary sensor point."""
    async_add_entities([PlcConnectivity(entry)])
    entry.runtime_data.points.async_setup_platform(
        "binary_sensor", point_binary_sensor, async_add_entities
    )


class PlcBinarySensor(PlcPointEntity, BinarySensorEntity):
    """A BOOL point (any non-zero number counts as on, unless codes or invert say otherwise)."""

    entity_description: PlcBinarySensorDescription

    @property
    def is_on(self) -> bool | None:
        """Return the point's state (its on/off codes and invert applied)."""
        return self.entity_description.convert.is_on(self.raw_value)
