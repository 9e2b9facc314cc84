"""Switches: writable BOOL points, or a state and a command at separate addresses.

A switch whose points name roles reads `state` (a contact, `Q21.7`) and writes `command`
(`M21.6`) as a level, or as a pulse for an impulse relay: sent only when the state differs.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from homeassistant.components.switch import (  # type: ignore[attr-defined]
    SwitchDeviceClass,
    SwitchEntity,
    SwitchEntityDescription,
)
from homeassistant.core import HomeAssistant
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from .composite_entity import PlcCompositeEntity, async_setup_composites
from .coordinator import PlcBridgeConfigEntry
from .entity import PlcPointDescription, PlcPointEntity, device_class, point_fields
from .model.points import PointConfig
from .plc import ValueKind

PARALLEL_UPDATES = 1


@dataclass(frozen=True, kw_only=True)
class PlcSwitchDescription(SwitchEntityDescription, PlcPointDescription):
    """A point shown as a switch."""


def point_switch(entry: PlcBridgeConfigEntry, config: PointConfig) -> PlcSwitch:
    """Return the switch of a point."""
    description = PlcSwitchDescription(
        **point_fields(entry, config), device_class=device_class(config, SwitchDeviceClass)
    )
    return PlcSwitch(entry, config, description)


async def async_setup_entry(
    hass: HomeAssistant,
    entry: PlcBridgeConfigEntry,
    async_add_entities: AddConfigEntryEntitiesCallback,
) -> None:
    """Add a switch for each switch point, and one for each state and command pair."""
    async_setup_composites(entry, "switch", PlcPartsSwitch, async_add_entities, point_switch)


class PlcSwitch(PlcPointEntity, SwitchEntity):
    """A BOOL point the user can set (an integer point is written its on/off codes, 1 or 0)."""

    entity_description: PlcSwitchDescription

    @property
    def is_on(self) -> bool | None:
        """Return the point's state (its on/off codes and invert applied)."""
        return self.entity_description.convert.is_on(self.raw_value)

    async def async_turn_on(self, **kwargs: Any) -> None:
        """Write true."""
        await self.async_write(self._state(on=True))

    async def async_turn_off(self, **kwargs: Any) -> None:
        """Write false."""
        await self.async_write(self._state(on=False))

    def _state(self, *, on: bool) -> bool | int | float:
        """Return the value that means on or off for the point's type, codes and invert."""
        description = self.entity_description
        return description.convert.state_value(on, boolean=description.kind is ValueKind.BOOL)


class PlcPartsSwitch(PlcCompositeEntity, SwitchEntity):
    """A switch with its state and its command at separate addresses."""

    @property
    def is_on(self) -> bool | None:
        """The state read (its codes and invert applied)."""
        return self.switched()

    async def async_turn_on(self, **kwargs: Any) -> None:
        """Switch on: the command's level, or a pulse if the state is off."""
        await self.async_switch(True)

    async def async_turn_off(self, **kwargs: Any) -> None:
        """Switch off: the command's level, or a pulse if the state is on."""
        await self.async_switch(False)
