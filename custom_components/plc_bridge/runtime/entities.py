"""The entities of a loaded entry's points: their devices, and entities that follow edits.

Adding, editing or removing points touches only the entities of those points: the others keep
their state, and the entry is not reloaded.
"""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from typing import Any

from homeassistant.config_entries import ConfigEntry
from homeassistant.core import HomeAssistant, callback
from homeassistant.helpers import device_registry as dr, entity_registry as er
from homeassistant.helpers.entity import Entity
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from ..const import (
    CONF_AREA,
    DOMAIN,
    SUBENTRY_DEVICE,
)
from ..model.composite import touched
from ..model.points import PointConfig, entry_points

type PointFactory = Callable[[ConfigEntry[Any], PointConfig], Entity | list[Entity]]
"""Makes a point's entity on one platform (or several: the named bits of an alarm word)."""


@callback
def async_register_devices(
    hass: HomeAssistant,
    entry: ConfigEntry[Any],
    plc: str,
    areas: dict[str, str | None] | None = None,
) -> None:
    """Create or update the device of every device subentry, hanging off the PLC's device.

    The link and the area are set through the registry itself, which both the oldest and the
    current supported Home Assistant take the same way; entities then name only identifiers.
    A device gets its subentry's area when it is made, and again when the device flow changes
    that area (`areas`: the area each subentry had when last seen); an area chosen in the
    device registry is kept otherwise.
    """
    registry = dr.async_get(hass)
    known = {
        identifier
        for device in dr.async_entries_for_config_entry(registry, entry.entry_id)
        for identifier in device.identifiers
    }
    for subentry in entry.subentries.values():
        if subentry.subentry_type != SUBENTRY_DEVICE:
            continue
        identifiers = {(DOMAIN, subentry.subentry_id)}
        new = not identifiers & known
        device = registry.async_get_or_create(
            config_entry_id=entry.entry_id,
            config_subentry_id=subentry.subentry_id,
            identifiers=identifiers,
            name=subentry.title,
        )
        changes: dict[str, Any] = {}
        if device.via_device_id != plc:
            changes["via_device_id"] = plc
        area, moved = subentry.data.get(CONF_AREA), False
        if areas is not None:
            moved = subentry.subentry_id in areas and areas[subentry.subentry_id] != area
            areas[subentry.subentry_id] = area
        if area and (new or moved):
            changes["area_id"] = area
        if not new and device.name != subentry.title:
            changes["name"] = subentry.title
        if changes:
            registry.async_update_device(device.id, **changes)


class PointEntities:
    """The point entities of one loaded entry, kept in step with its device subentries."""

    def __init__(self, entry: ConfigEntry[Any]) -> None:
        """Start from the points the entry holds now; platforms register as they set up."""
        self._entry = entry
        self.configs = entry_points(entry)
        self._platforms: dict[str, tuple[PointFactory, AddConfigEntryEntitiesCallback]] = {}
        self._entities: dict[str, list[Entity]] = {}
        self._lock = asyncio.Lock()
        self.areas: dict[str, str | None] = {}  # each device subentry's area, as last seen

    @callback
    def async_setup_platform(
        self, platform: str, factory: PointFactory, add: AddConfigEntryEntitiesCallback
    ) -> None:
        """Remember how a platform makes and adds entities, and add its points."""
        self._platforms[platform] = (factory, add)
        self._add(
            self._make(
                [config for config in self.configs.values() if platform in config.platforms],
                platform,
            )
        )

    def _make(
        self, configs: list[PointConfig], only: str | None = None
    ) -> list[tuple[PointConfig, str, Entity]]:
        """Make the entities of these points (on one platform), not added yet."""
        made: list[tuple[PointConfig, str, Entity]] = []
        for config in configs:
            for platform in config.platforms:
                if platform not in self._platforms or only not in (None, platform):
                    continue
                result = self._platforms[platform][0](self._entry, config)
                entities = result if isinstance(result, list) else [result]
                made += [(config, platform, entity) for entity in entities]
        return made

    def _add(self, made: list[tuple[PointConfig, str, Entity]]) -> None:
        """Add made entities, each under its point's device subentry."""
        groups: dict[tuple[str, str], list[Entity]] = {}
        for config, platform, entity in made:
            self._entities.setdefault(config.point_id, []).append(entity)
            groups.setdefault((platform, config.subentry_id), []).append(entity)
        for (platform, subentry_id), entities in groups.items():
            self._platforms[platform][1](entities, config_subentry_id=subentry_id)

    async def async_sync(self, hass: HomeAssistant, plc_device: str) -> None:
        """Follow edited device subentries: only the points that changed get new entities."""
        async with self._lock:
            entry = self._entry
            new = entry_points(entry)
            old = self.configs
            changed = touched(
                [pid for pid in old.keys() | new.keys() if old.get(pid) != new.get(pid)], old, new
            )
            gone = [pid for pid in old if pid in changed]
            self.configs = new  # what the factories group composite entities from
            made = self._make([config for pid, config in new.items() if pid in changed])
            kept = {(platform, entity.unique_id) for _, platform, entity in made}
            registry = er.async_get(hass)
            for point_id in gone:
                for entity in self._entities.pop(point_id, []):
                    if getattr(entity, "hass", None) is None:  # never added
                        continue
                    if (entity.entity_id.partition(".")[0], entity.unique_id) in kept:
                        await entity.async_remove()  # keeps its registry entry: same id, history
                    elif registry.async_get(entity.entity_id):
                        registry.async_remove(entity.entity_id)  # a removed point or named bit
            async_register_devices(hass, entry, plc_device, self.areas)
            entry.runtime_data.coordinator.async_set_points(new)
            self._add(made)
