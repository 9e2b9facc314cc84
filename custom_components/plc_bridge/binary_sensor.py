"""Binary sensors: BOOL points, shown on or off."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from homeassistant.components.binary_sensor import (  # type: ignore[attr-defined]
    BinarySensorDeviceClass,
    BinarySensorEntity,
    BinarySensorEntityDescription,
)
from homeassistant.core import HomeAssistant
from homeassistant.helpers.entity import Entity
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from .coordinator import PlcBridgeConfigEntry
from .entity import PlcPointDescription, PlcPointEntity, device_class, point_fields
from .link import PlcConnectivity
from .model.alarm import bit_set, word_bits
from .model.points import PointConfig

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


@dataclass(frozen=True, kw_only=True)
class PlcBitDescription(BinarySensorEntityDescription, PlcPointDescription):
    """One named bit of an alarm word."""

    bit: int


def bit_sensors(entry: PlcBridgeConfigEntry, config: PointConfig) -> list[Entity]:
    """Return a binary sensor for each named bit of an alarm word."""
    fields = point_fields(entry, config)
    chosen = device_class(config, BinarySensorDeviceClass) or BinarySensorDeviceClass.PROBLEM
    return [
        PlcBitSensor(
            entry,
            config,
            PlcBitDescription(
                **{**fields, "key": f"{config.point_id}_bit{bit}", "name": label},
                bit=bit,
                device_class=chosen,
            ),
        )
        for bit, label in word_bits(config)
    ]


class PlcBitSensor(PlcPointEntity, BinarySensorEntity):
    """One named bit of an alarm or status word."""

    entity_description: PlcBitDescription

    @property
    def is_on(self) -> bool | None:
        """Return whether the bit is set."""
        return bit_set(self.raw_value, self.entity_description.bit)

    def observed(self) -> Any:
        """The bit as read in the last poll (other bits of the word write no state)."""
        return self.is_on
