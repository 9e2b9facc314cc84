"""Water heaters built from several points: temperatures, an operation mode map, on/off.

Roles (model/kinds.py): `current_temperature` (read), `target_temperature` (read and written;
its point's min, max and step bound what may be set, else its linear range), `operation_mode`
(a value map onto Home Assistant's water heater modes, `0=off;1=eco;2=performance`) and
`on_off` (a switch point: off shows as mode off, the mode is kept). Without a mode map the
state is the on/off part's, unknown without either.
"""

from __future__ import annotations

from typing import Any

from homeassistant.components.water_heater import (  # type: ignore[attr-defined]
    ATTR_OPERATION_MODE,
    WaterHeaterEntity,
    WaterHeaterEntityFeature,
)
from homeassistant.const import ATTR_TEMPERATURE, STATE_OFF, STATE_ON
from homeassistant.core import HomeAssistant
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from .composite_entity import Part, PlcTemperatureEntity, async_setup_composites
from .coordinator import PlcBridgeConfigEntry
from .model.composite import Composite
from .plc import Value

PARALLEL_UPDATES = 1


async def async_setup_entry(
    hass: HomeAssistant,
    entry: PlcBridgeConfigEntry,
    async_add_entities: AddConfigEntryEntitiesCallback,
) -> None:
    """Add a water heater for each group of water heater points."""
    async_setup_composites(entry, "water_heater", PlcWaterHeater, async_add_entities)


class PlcWaterHeater(PlcTemperatureEntity, WaterHeaterEntity):
    """A water heater whose parts are points of one machine."""

    def __init__(
        self, entry: PlcBridgeConfigEntry, group: Composite, parts: dict[str, Part]
    ) -> None:
        """Work out the modes, limits and features from the parts."""
        super().__init__(entry, group, parts)
        self._attr_supported_features = WaterHeaterEntityFeature(self.features())
        self.set_temperature_limits(parts)
        mode = parts.get("operation_mode")
        modes = [label for _, label in mode.conversion.value_map] if mode else []
        if modes and "on_off" in parts and STATE_OFF not in modes:
            modes.append(STATE_OFF)
        self._attr_operation_list = modes or None

    @property
    def current_operation(self) -> str | None:
        """Off while the on/off part is off, else the mode map's label (on/off without a map)."""
        on = self.on("on_off")
        if on is False:
            return STATE_OFF
        if "operation_mode" in self.parts:
            return self.label("operation_mode")
        return None if on is None else STATE_ON

    async def async_set_temperature(self, **kwargs: Any) -> None:
        """Write the target temperature (refused outside min..max before sending), and a mode."""
        if ATTR_TEMPERATURE in kwargs and "target_temperature" in self.parts:
            value = float(kwargs[ATTR_TEMPERATURE])
            await self.async_write_number("target_temperature", value, self.min_temp, self.max_temp)
        if kwargs.get(ATTR_OPERATION_MODE) is not None:
            await self.async_set_operation_mode(str(kwargs[ATTR_OPERATION_MODE]))

    async def async_set_operation_mode(self, operation_mode: str) -> None:
        """Write the mode's code; off through the on/off part where there is one (mode kept)."""
        values: dict[str, Value] = {}
        if "on_off" in self.parts:
            values["on_off"] = self.parts["on_off"].level(on=operation_mode != STATE_OFF)
        mode = self.parts.get("operation_mode")
        if mode is not None and (operation_mode != STATE_OFF or "on_off" not in self.parts):
            values["operation_mode"] = mode.conversion.code(operation_mode)
        if values:
            await self.async_write_parts(values)

    async def async_turn_on(self, **kwargs: Any) -> None:
        """Switch on through the on/off part."""
        await self.async_write_parts({"on_off": self.parts["on_off"].level(on=True)})

    async def async_turn_off(self, **kwargs: Any) -> None:
        """Switch off through the on/off part."""
        await self.async_write_parts({"on_off": self.parts["on_off"].level(on=False)})
