"""Fans built from several points: on and off, a speed as a percentage, preset modes.

Roles: `command` (written as a level, or pulsed when the state differs), `state` (read),
`percentage` (a word whose linear range shows 0-100 %), `preset` (a value map whose labels
are the preset modes, `0=Low;1=High;2=Auto`). A fan with a speed and no command switches
by its speed: on at 100 %, off at 0 %.
"""

from __future__ import annotations

from typing import Any

from homeassistant.components.fan import (  # type: ignore[attr-defined]
    FanEntity,
    FanEntityFeature,
)
from homeassistant.core import HomeAssistant
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from .composite_entity import Part, PlcCompositeEntity, async_setup_composites
from .coordinator import PlcBridgeConfigEntry
from .model.composite import Composite
from .plc import Value, ValueKind

PARALLEL_UPDATES = 1
FULL = 100


async def async_setup_entry(
    hass: HomeAssistant,
    entry: PlcBridgeConfigEntry,
    async_add_entities: AddConfigEntryEntitiesCallback,
) -> None:
    """Add a fan for each group of fan points."""
    async_setup_composites(entry, "fan", PlcFan, async_add_entities)


class PlcFan(PlcCompositeEntity, FanEntity):
    """A fan whose parts are points of one machine."""

    def __init__(
        self, entry: PlcBridgeConfigEntry, group: Composite, parts: dict[str, Part]
    ) -> None:
        """Work out the speed and the presets from the parts."""
        super().__init__(entry, group, parts)
        if (preset := parts.get("preset")) is not None:
            self._attr_preset_modes = [label for _, label in preset.conversion.value_map]
        self._attr_supported_features = FanEntityFeature(self.features())

    @property
    def is_on(self) -> bool | None:
        """The state read; without a state or command, a speed above 0."""
        if "state" in self.parts or "command" in self.parts:
            return self.switched()
        value = self.number("percentage")
        return None if value is None else value > 0

    @property
    def percentage(self) -> int | None:
        """The speed read, 0-100 %."""
        value = self.number("percentage")
        return None if value is None else round(min(max(value, 0), FULL))

    @property
    def preset_mode(self) -> str | None:
        """The preset the map names."""
        return self.label("preset")

    def _speed(self, percentage: float) -> dict[str, Value]:
        """Return the speed part's raw value for a percentage."""
        part = self.parts["percentage"]
        return {
            "percentage": part.conversion.raw(percentage, integer=part.kind is ValueKind.INTEGER)
        }

    async def async_turn_on(
        self, percentage: int | None = None, preset_mode: str | None = None, **kwargs: Any
    ) -> None:
        """Switch on, at the speed or preset asked for."""
        also: dict[str, Value] = {}
        if "percentage" in self.parts and percentage is not None:
            also = self._speed(percentage)
        elif "percentage" in self.parts and "command" not in self.parts and preset_mode is None:
            also = self._speed(FULL)
        if preset_mode is not None and "preset" in self.parts:
            also["preset"] = self.parts["preset"].conversion.code(preset_mode)
        await self.async_switch(True, also)

    async def async_turn_off(self, **kwargs: Any) -> None:
        """Switch off (a fan without a command: to 0 %)."""
        also = self._speed(0) if "command" not in self.parts else {}
        await self.async_switch(False, also)

    async def async_set_percentage(self, percentage: int) -> None:
        """Run at this speed; 0 switches off."""
        if percentage == 0:
            await self.async_turn_off()
        else:
            await self.async_turn_on(percentage=percentage)

    async def async_set_preset_mode(self, preset_mode: str) -> None:
        """Write the preset's code."""
        await self.async_write_parts({"preset": self.parts["preset"].conversion.code(preset_mode)})
