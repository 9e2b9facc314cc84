"""Buttons: pressing writes a point's "on" value once, or pulses it on, then off.

Without a pulse duration (the safe mode) a press writes the "on" value and the PLC program
resets the bit. With one (0.1-60 s) the "off" value follows after that time (pulse.py: a
failed off-write retried, then reported; a pending one sent at unload or stop).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from homeassistant.components.button import ButtonEntity, ButtonEntityDescription
from homeassistant.core import HomeAssistant
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from .coordinator import PlcBridgeConfigEntry
from .entity import PlcPointDescription, PlcPointEntity, point_fields
from .plc import ValueKind
from .points import PointConfig
from .pulse import Pulse, pulse_seconds

PARALLEL_UPDATES = 1


@dataclass(frozen=True, kw_only=True)
class PlcButtonDescription(ButtonEntityDescription, PlcPointDescription):
    """A point written by a button: `pulse` seconds on, or 0 for a single write."""

    pulse: float = 0.0


def point_button(entry: PlcBridgeConfigEntry, config: PointConfig) -> PlcButton:
    """Return the button of a point."""
    pulse = pulse_seconds(config.data)
    description = PlcButtonDescription(**point_fields(entry, config), pulse=pulse)
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
        self._pulse = Pulse(
            entry,
            description.key,
            name=config.name,
            address=description.point.address,
            write_off=lambda: self.async_write(self._level(on=False)),
        )

    def observed(self) -> Any:
        """A button shows no value: only its availability changes its state."""
        return None

    def _level(self, *, on: bool) -> bool | int | float:
        """Return the raw value that means on or off for this point."""
        description = self.entity_description
        return description.convert.state_value(on, boolean=description.kind is ValueKind.BOOL)

    async def async_press(self) -> None:
        """Write "on"; with a pulse, write "off" when it ends (a new press restarts it)."""
        self._pulse.cancel()
        await self.async_write(self._level(on=True))
        if self.entity_description.pulse > 0:
            self._pulse.start(self.hass, self.entity_description.pulse)

    async def async_will_remove_from_hass(self) -> None:
        """Removed (unload, reload, edit) mid-pulse: end the pulse now."""
        await self._pulse.async_end_now()
        await super().async_will_remove_from_hass()
