"""Selects: writable points with a value map, shown and set by their labels."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from homeassistant.components.select import SelectEntity, SelectEntityDescription
from homeassistant.core import HomeAssistant
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from .const import LOGGER
from .coordinator import PlcBridgeConfigEntry
from .entity import PlcPointDescription, PlcPointEntity, point_fields
from .model.conversion import check_unmapped, labels
from .model.points import PointConfig

PARALLEL_UPDATES = 1


@dataclass(frozen=True, kw_only=True)
class PlcSelectDescription(SelectEntityDescription, PlcPointDescription):
    """A point shown as a select."""


def point_select(entry: PlcBridgeConfigEntry, config: PointConfig) -> PlcSelect:
    """Return the select of a point: its options are the labels of its value map."""
    fields = point_fields(entry, config)
    options = labels(fields["conversion"].value_map)
    return PlcSelect(entry, config, PlcSelectDescription(**fields, options=options))


async def async_setup_entry(
    hass: HomeAssistant,
    entry: PlcBridgeConfigEntry,
    async_add_entities: AddConfigEntryEntitiesCallback,
) -> None:
    """Add a select for each select point."""
    entry.runtime_data.points.async_setup_platform("select", point_select, async_add_entities)


class PlcSelect(PlcPointEntity, SelectEntity):
    """A point the user sets by label; a raw value outside the map shows as unknown."""

    entity_description: PlcSelectDescription

    def __init__(
        self, entry: PlcBridgeConfigEntry, config: PointConfig, description: PlcSelectDescription
    ) -> None:
        """Bind the select to its point and note raw values outside the map."""
        super().__init__(entry, config, description)
        self._label = config.name
        self._unmapped = False

    @property
    def current_option(self) -> str | None:
        """Return the label of the point's value."""
        return self.entity_description.convert.label(self.raw_value)

    def observed(self) -> Any:
        """The point's value as read in the last poll (a value outside the map logged once)."""
        self._unmapped = check_unmapped(
            LOGGER, self._label, self.entity_description.convert, self.raw_value, self._unmapped
        )
        return self.raw_value

    async def async_select_option(self, option: str) -> None:
        """Write the raw value of the chosen label."""
        await self.async_write(self.entity_description.convert.code(option))
