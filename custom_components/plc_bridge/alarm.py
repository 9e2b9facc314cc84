"""Alarm and status words: one integer point whose named bits are each a binary sensor.

The point's own platform is `event` (one event entity fires `raised` / `cleared` with the
bit's name); its `bits` (`0=Overheat;3=Low water`) add a binary sensor per named bit, of
device class problem unless the point names another. All read the one point of the poll.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from homeassistant.components.binary_sensor import (  # type: ignore[attr-defined]
    BinarySensorDeviceClass,
    BinarySensorEntity,
    BinarySensorEntityDescription,
)
from homeassistant.helpers.entity import Entity

from .const import CONF_BITS
from .conversion import Pairs, stored_pairs
from .coordinator import PlcBridgeConfigEntry
from .entity import PlcPointDescription, PlcPointEntity, device_class, point_fields
from .plc import Value
from .points import PointConfig


def word_bits(config: PointConfig) -> Pairs:
    """Return the named bits of an alarm word point."""
    return stored_pairs(config.data, CONF_BITS)


def bit_set(raw: Value | None, bit: int) -> bool | None:
    """Return whether a bit of a raw integer is set, None for no integer."""
    if isinstance(raw, bool) or not isinstance(raw, int):
        return None
    return bool(raw >> bit & 1)


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
