"""Lights from several points: a state, a command (level or pulse) and a dimmer's brightness.

Roles: `command` (written as a level, or pulsed for an impulse relay when the state differs),
`state` (read), `brightness` (a word whose linear range shows 0-100 %; Home Assistant's
0-255 brightness is converted to that). A light with a brightness and no command switches by
its brightness: on at 100 %, off at 0 %.
"""

from __future__ import annotations

from typing import Any

from homeassistant.components.light import (  # type: ignore[attr-defined]
    ATTR_BRIGHTNESS,
    ColorMode,
    LightEntity,
)
from homeassistant.core import HomeAssistant
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from .composite_entity import Part, PlcCompositeEntity, async_setup_composites
from .coordinator import PlcBridgeConfigEntry
from .model.composite import Composite
from .plc import Value, ValueKind

PARALLEL_UPDATES = 1
FULL = 100
BRIGHTEST = 255


async def async_setup_entry(
    hass: HomeAssistant,
    entry: PlcBridgeConfigEntry,
    async_add_entities: AddConfigEntryEntitiesCallback,
) -> None:
    """Add a light for each group of light points."""
    async_setup_composites(entry, "light", PlcLight, async_add_entities)


class PlcLight(PlcCompositeEntity, LightEntity):
    """A light whose parts are points of one machine."""

    def __init__(
        self, entry: PlcBridgeConfigEntry, group: Composite, parts: dict[str, Part]
    ) -> None:
        """Dimmable when it has a brightness part."""
        super().__init__(entry, group, parts)
        mode = ColorMode.BRIGHTNESS if "brightness" in parts else ColorMode.ONOFF
        self._attr_color_mode = mode
        self._attr_supported_color_modes = {mode}

    @property
    def brightness(self) -> int | None:
        """The brightness read, 0-100 % shown as Home Assistant's 0-255."""
        value = self.number("brightness")
        if value is None:
            return None
        return round(min(max(value, 0), FULL) * BRIGHTEST / FULL)

    @property
    def is_on(self) -> bool | None:
        """The state read; without one, a brightness above 0."""
        if "state" in self.parts or "command" in self.parts:
            return self.switched()
        value = self.number("brightness")
        return None if value is None else value > 0

    def _brightness(self, brightness: float) -> dict[str, Value]:
        """Return the brightness part's raw value for a 0-255 brightness."""
        part = self.parts["brightness"]
        percent = float(brightness) * FULL / BRIGHTEST
        return {"brightness": part.conversion.raw(percent, integer=part.kind is ValueKind.INTEGER)}

    async def async_turn_on(self, **kwargs: Any) -> None:
        """Switch on, with the brightness asked for if there is a brightness part."""
        also: dict[str, Value] = {}
        if "brightness" in self.parts and ATTR_BRIGHTNESS in kwargs:
            also = self._brightness(kwargs[ATTR_BRIGHTNESS])
        elif "brightness" in self.parts and "command" not in self.parts:
            also = self._brightness(BRIGHTEST)
        await self.async_switch(True, also)

    async def async_turn_off(self, **kwargs: Any) -> None:
        """Switch off (a light without a command: to 0 %)."""
        also = self._brightness(0) if "command" not in self.parts else {}
        await self.async_switch(False, also)
