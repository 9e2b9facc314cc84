"""Climate entities built from several points: temperatures, an HVAC mode map, an action map.

Roles: `current_temperature` (read), `target_temperature` (read and written; its point's
min, max and step bound what may be set, else its linear range), `hvac_mode` (a value map
onto Home Assistant's modes, `0=off;1=heat;2=cool;3=auto`), `hvac_action` (a value map onto
its actions, `0=idle;1=heating`), `on_off` (a switch point; off shows as mode off) and
`preset` (a value map whose labels are the presets, `0=Comfort;1=Eco`).
"""

from __future__ import annotations

from typing import Any

from homeassistant.components.climate import ClimateEntity
from homeassistant.components.climate.const import ClimateEntityFeature, HVACAction, HVACMode
from homeassistant.const import (
    ATTR_TEMPERATURE,
)
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import ServiceValidationError
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from .composite_entity import Part, PlcTemperatureEntity, async_setup_composites
from .const import DOMAIN
from .coordinator import PlcBridgeConfigEntry
from .model.composite import Composite
from .plc import Value, ValueKind

PARALLEL_UPDATES = 1


async def async_setup_entry(
    hass: HomeAssistant,
    entry: PlcBridgeConfigEntry,
    async_add_entities: AddConfigEntryEntitiesCallback,
) -> None:
    """Add a climate entity for each group of climate points."""
    async_setup_composites(entry, "climate", PlcClimate, async_add_entities)


class PlcClimate(PlcTemperatureEntity, ClimateEntity):
    """A thermostat whose parts are points of one machine."""

    def __init__(
        self, entry: PlcBridgeConfigEntry, group: Composite, parts: dict[str, Part]
    ) -> None:
        """Work out the modes, limits and features from the parts."""
        super().__init__(entry, group, parts)
        mode = parts.get("hvac_mode")
        modes = [HVACMode(label) for _, label in mode.conversion.value_map] if mode else []
        if not modes:
            modes = [HVACMode.HEAT]
        if "on_off" in parts and HVACMode.OFF not in modes:
            modes.insert(0, HVACMode.OFF)
        self._attr_hvac_modes = modes
        features = ClimateEntityFeature(self.features())
        if HVACMode.OFF in modes:
            features |= ClimateEntityFeature.TURN_OFF | ClimateEntityFeature.TURN_ON
        self.set_temperature_limits(parts)
        if (preset := parts.get("preset")) is not None:
            self._attr_preset_modes = [label for _, label in preset.conversion.value_map]
        self._attr_supported_features = features

    @property
    def hvac_mode(self) -> HVACMode | None:
        """Off while the on/off part is off, else the mode map's label (heat without a map)."""
        if self.on("on_off") is False:
            return HVACMode.OFF
        if "hvac_mode" not in self.parts:
            on = self.on("on_off") if "on_off" in self.parts else True
            return None if on is None else HVACMode.HEAT
        label = self.label("hvac_mode")
        return None if label is None else HVACMode(label)

    @property
    def hvac_action(self) -> HVACAction | None:
        """The action the status map names."""
        label = self.label("hvac_action")
        return None if label is None else HVACAction(label)

    @property
    def preset_mode(self) -> str | None:
        """The preset the map names."""
        return self.label("preset")

    async def async_set_preset_mode(self, preset_mode: str) -> None:
        """Write the preset's code."""
        await self.async_write_parts({"preset": self.parts["preset"].conversion.code(preset_mode)})

    async def async_set_temperature(self, **kwargs: Any) -> None:
        """Write the target temperature (refused outside min..max before sending)."""
        if ATTR_TEMPERATURE not in kwargs or "target_temperature" not in self.parts:
            return
        value = float(kwargs[ATTR_TEMPERATURE])
        if not self.min_temp <= value <= self.max_temp:
            raise ServiceValidationError(
                translation_domain=DOMAIN,
                translation_key="out_of_range",
                translation_placeholders={
                    "value": f"{value:g}",
                    "min": f"{self.min_temp:g}",
                    "max": f"{self.max_temp:g}",
                },
            )
        part = self.parts["target_temperature"]
        raw = part.conversion.raw(value, integer=part.kind is ValueKind.INTEGER)
        await self.async_write_parts({"target_temperature": raw})

    async def async_set_hvac_mode(self, hvac_mode: HVACMode) -> None:
        """Write the mode's code; off through the on/off part where there is one."""
        values: dict[str, Value] = {}
        if "on_off" in self.parts:
            values["on_off"] = self.parts["on_off"].level(on=hvac_mode != HVACMode.OFF)
        mode = self.parts.get("hvac_mode")
        if mode is not None and (hvac_mode != HVACMode.OFF or "on_off" not in self.parts):
            values["hvac_mode"] = mode.conversion.code(str(hvac_mode))
        if values:
            await self.async_write_parts(values)
            self.supervisor.watch("off" if hvac_mode == HVACMode.OFF else "on")

    def follows(self, commanded: str) -> bool | None:
        """Whether the mode read is off when off was commanded, another one when on was."""
        mode = self.hvac_mode
        return None if mode is None else (mode != HVACMode.OFF) == (commanded == "on")

    async def async_turn_on(self) -> None:
        """Switch on through the on/off part, else the first mode that is not off."""
        if "on_off" in self.parts:
            await self.async_write_parts({"on_off": self.parts["on_off"].level(on=True)})
            self.supervisor.watch("on")
            return
        await self.async_set_hvac_mode(next(m for m in self.hvac_modes if m != HVACMode.OFF))

    async def async_turn_off(self) -> None:
        """Switch off."""
        await self.async_set_hvac_mode(HVACMode.OFF)
