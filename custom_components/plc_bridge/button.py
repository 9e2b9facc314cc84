"""Buttons: pressing writes a point's "on" value once, or pulses it on, then off.

Without a pulse duration (the safe mode) a press writes the "on" value and the PLC program
resets the bit. With one (0.1-60 s) the "off" value follows after that time, whatever the
outcome of the on-write (outputs.py: the off retried until confirmed, a repair issue meanwhile,
sent at once at unload or stop); a press during a pulse keeps its end.
"""

from __future__ import annotations

import asyncio
from dataclasses import dataclass
from typing import Any

from homeassistant.components.button import ButtonEntity, ButtonEntityDescription
from homeassistant.core import HomeAssistant, callback
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from .coordinator import PlcBridgeConfigEntry
from .entity import PlcPointDescription, PlcPointEntity, point_fields
from .model.points import PointConfig
from .plc import ValueKind
from .runtime.issues import PULSE_FAILED
from .runtime.outputs import Output, async_send

PARALLEL_UPDATES = 1


@dataclass(frozen=True, kw_only=True)
class PlcButtonDescription(ButtonEntityDescription, PlcPointDescription):
    """A point written by a button: `pulse` seconds on, or 0 for a single write."""

    pulse: float = 0.0


def point_button(entry: PlcBridgeConfigEntry, config: PointConfig) -> PlcButton:
    """Return the button of a point."""
    description = PlcButtonDescription(**point_fields(entry, config), pulse=config.pulse_seconds)
    return PlcButton(entry, config, description)


async def async_setup_entry(
    hass: HomeAssistant,
    entry: PlcBridgeConfigEntry,
    async_add_entities: AddConfigEntryEntitiesCallback,
) -> None:
    """Add a button for each button point."""
    entry.runtime_data.points.async_setup_platform("button", point_button, async_add_entities)


class PlcButton(PlcPointEntity, ButtonEntity):
    """A point written when pressed (and written back after a pulse)."""

    entity_description: PlcButtonDescription

    def __init__(
        self, entry: PlcBridgeConfigEntry, config: PointConfig, description: PlcButtonDescription
    ) -> None:
        """Bind the button to its point; no pulse runs yet."""
        super().__init__(entry, config, description)
        point = description.point
        off = {point: self._level(on=False)}
        self._output = Output(
            entry,
            asyncio.Lock(),
            (PULSE_FAILED, description.key),
            name=config.name,
            address=point.address,
            write_off=lambda: async_send(self.coordinator, off, release=True),
            read_back=self._read_back_later,
        )

    def observed(self) -> Any:
        """A button shows no value: only its availability changes its state."""
        return None

    def _level(self, *, on: bool) -> bool | int | float:
        """Return the raw value that means on or off for this point."""
        description = self.entity_description
        return description.convert.state_value(on, boolean=description.kind is ValueKind.BOOL)

    @callback
    def _read_back_later(self) -> None:
        """Have the point read back by a poll soon, without waiting for it."""
        self.coordinator.ask_back(self.read_points())
        self.coordinator.config_entry.async_create_background_task(
            self.hass, self.coordinator.async_request_refresh(), f"{self.entity_id} read back"
        )

    async def async_press(self) -> None:
        """Write "on"; with a pulse, "off" when it ends (a press during a pulse keeps its end)."""
        description = self.entity_description
        if description.pulse <= 0:
            await self.async_write(self._level(on=True))
            return
        on = {description.point: self._level(on=True)}
        if await self._output.async_turn_on(
            lambda: async_send(self.coordinator, on, release=False), description.pulse
        ):
            self.coordinator.ask_back(self.read_points())
            await self.coordinator.async_request_refresh()

    async def async_added_to_hass(self) -> None:
        """Follow Home Assistant's stop; release what a previous setup left on."""
        await super().async_added_to_hass()
        if self.entity_description.pulse > 0:
            self.async_on_remove(self._output.async_attach(self.hass))

    async def async_will_remove_from_hass(self) -> None:
        """Removed (unload, reload, edit) mid-pulse: end the pulse now."""
        await self._output.async_end()
        await super().async_will_remove_from_hass()
