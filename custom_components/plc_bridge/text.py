"""Texts: writable STRING points, and durations as hh:mm:ss.zzz (as TecoApi TIME showed)."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import timedelta

from homeassistant.components.text import TextEntity, TextEntityDescription
from homeassistant.core import HomeAssistant
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from .coordinator import PlcBridgeConfigEntry
from .entity import PlcPointDescription, PlcPointEntity, point_fields
from .model.points import PointConfig
from .plc.durations import clock_text

PARALLEL_UPDATES = 1


@dataclass(frozen=True, kw_only=True)
class PlcTextDescription(TextEntityDescription, PlcPointDescription):
    """A point shown as an editable text."""


def point_text(entry: PlcBridgeConfigEntry, config: PointConfig) -> PlcText:
    """Return the text entity of a point; the vendor's check refuses what does not fit."""
    return PlcText(entry, config, PlcTextDescription(**point_fields(entry, config), native_max=255))


async def async_setup_entry(
    hass: HomeAssistant,
    entry: PlcBridgeConfigEntry,
    async_add_entities: AddConfigEntryEntitiesCallback,
) -> None:
    """Add a text entity for each text point."""
    entry.runtime_data.points.async_setup_platform("text", point_text, async_add_entities)


class PlcText(PlcPointEntity, TextEntity):
    """A STRING point the user can set."""

    entity_description: PlcTextDescription

    @property
    def native_value(self) -> str | None:
        """Return the point's text (a duration as hh:mm:ss.zzz)."""
        value = self.raw_value
        if isinstance(value, timedelta):
            return clock_text(value)
        return None if value is None else str(value)

    async def async_set_value(self, value: str) -> None:
        """Write the text (ASCII, length or duration are checked by the vendor before sending)."""
        await self.async_write(value)
