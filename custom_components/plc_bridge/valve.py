"""Valves built from several points: the roles and behaviour of a cover (cover.py).

`open`, `close`, `stop` commands (level or pulse), `position` and `set_position` (0-100 %
through the point's linear range, invertible), `open_limit` and `closed_limit` switches, or a
`status` map onto open, closed, opening, closing. A valve reports a position when it has one.
Open and close send their commands where the valve has them (Home Assistant would write 100 %
and 0 % to a valve that can be set to a position), the position where it has only that.
"""

from __future__ import annotations

from homeassistant.components.valve import (  # type: ignore[attr-defined]
    ValveEntity,
    ValveEntityFeature,
)
from homeassistant.core import HomeAssistant
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from .composite_entity import Part, async_setup_composites
from .coordinator import PlcBridgeConfigEntry
from .cover import FULL, Travel
from .model.composite import Composite

PARALLEL_UPDATES = 1


async def async_setup_entry(
    hass: HomeAssistant,
    entry: PlcBridgeConfigEntry,
    async_add_entities: AddConfigEntryEntitiesCallback,
) -> None:
    """Add a valve for each group of valve points."""
    async_setup_composites(entry, "valve", PlcValve, async_add_entities)


class PlcValve(Travel, ValveEntity):
    """A valve whose parts are points of one machine."""

    def __init__(
        self, entry: PlcBridgeConfigEntry, group: Composite, parts: dict[str, Part]
    ) -> None:
        """Work out what the valve can do from the parts it has."""
        super().__init__(entry, group, parts)
        self._attr_supported_features = ValveEntityFeature(self.features())
        self._attr_reports_position = "position" in parts or "set_position" in parts

    @property
    def current_valve_position(self) -> int | None:
        """The position read, 0 closed to 100 open."""
        return self._position()

    # Home Assistant's final handlers write 100 % and 0 % to a valve that takes a position,
    # which would never send the valve's own open and close commands.
    async def async_handle_open_valve(self) -> None:  # type: ignore[misc]
        """Open by the open command (or step relay) where there is one, else to 100 %."""
        await self._async_move("open", FULL)

    async def async_handle_close_valve(self) -> None:  # type: ignore[misc]
        """Close by the close command (or step relay) where there is one, else to 0 %."""
        await self._async_move("close", 0)

    async def async_open_valve(self) -> None:
        """Send the open command, or move to 100 %."""
        await self._async_move("open", FULL)

    async def async_close_valve(self) -> None:
        """Send the close command, or move to 0 %."""
        await self._async_move("close", 0)

    async def async_stop_valve(self) -> None:
        """Send the stop command."""
        await self._async_move("stop", None)

    async def async_set_valve_position(self, position: int) -> None:
        """Write the position through the part's range."""
        await self._async_set_position(float(position))
