"""Switches: writable BOOL points."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from homeassistant.components.switch import (
    SwitchDeviceClass,
    SwitchEntity,
    SwitchEntityDescription,
)
from homeassistant.config_entries import ConfigSubentry
from homeassistant.core import HomeAssistant
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from .coordinator import PlcBridgeConfigEntry
from .entity import (
    PlcPointDescription,
    PlcPointEntity,
    add_point_entities,
    device_class,
    point_fields,
)
from .plc import ValueKind

PARALLEL_UPDATES = 1


@dataclass(frozen=True, kw_only=True)
class PlcSwitchDescription(SwitchEntityDescription, PlcPointDescription):
    """A point shown as a switch."""


def point_switch(entry: PlcBridgeConfigEntry, subentry: ConfigSubentry) -> PlcSwitch:
    """Return the switch of a point."""
    description = PlcSwitchDescription(
        **point_fields(entry, subentry), device_class=device_class(subentry, SwitchDeviceClass)
    )
    return PlcSwitch(entry, description)


async def async_setup_entry(
    hass: HomeAssistant,
    entry: PlcBridgeConfigEntry,
    async_add_entities: AddConfigEntryEntitiesCallback,
) -> None:
    """Add a switch for each switch point."""
    add_point_entities(entry, async_add_entities, "switch", point_switch)


class PlcSwitch(PlcPointEntity, SwitchEntity):
    """A BOOL point the user can set (an integer point is written 1 or 0)."""

    entity_description: PlcSwitchDescription

    @property
    def is_on(self) -> bool | None:
        """Return the point's state."""
        value = self.raw_value
        return None if value is None else bool(value)

    async def async_turn_on(self, **kwargs: Any) -> None:
        """Write true."""
        await self.async_write(self._state(on=True))

    async def async_turn_off(self, **kwargs: Any) -> None:
        """Write false."""
        await self.async_write(self._state(on=False))

    def _state(self, *, on: bool) -> bool | int:
        """Return the value that means on or off for the point's type."""
        return on if self.entity_description.kind is ValueKind.BOOL else int(on)
