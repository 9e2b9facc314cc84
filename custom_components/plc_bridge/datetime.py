"""Date and time entities: DATE and DT points, and the PLC clock where the PLC reports it."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime

from homeassistant.components.datetime import DateTimeEntity, DateTimeEntityDescription
from homeassistant.const import EntityCategory
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import Unauthorized, UnknownUser
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from .coordinator import PlcBridgeConfigEntry
from .entity import (
    PlcEntity,
    PlcPointDescription,
    PlcPointEntity,
    async_remove_entity,
    point_fields,
)
from .model.points import PointConfig

PARALLEL_UPDATES = 1


@dataclass(frozen=True, kw_only=True)
class PlcDateTimeDescription(DateTimeEntityDescription, PlcPointDescription):
    """A point shown as a date and time."""


def point_datetime(entry: PlcBridgeConfigEntry, config: PointConfig) -> PlcDateTime:
    """Return the date and time entity of a point."""
    return PlcDateTime(entry, config, PlcDateTimeDescription(**point_fields(entry, config)))


async def async_setup_entry(
    hass: HomeAssistant,
    entry: PlcBridgeConfigEntry,
    async_add_entities: AddConfigEntryEntitiesCallback,
) -> None:
    """Add a date and time entity for each datetime point, and the clock if it can be set."""
    runtime = entry.runtime_data
    if runtime.coordinator.data.status.clock is not None and runtime.client.can_set_clock:
        async_add_entities([PlcClock(entry)])
    else:  # no longer settable (the clock variable was taken away): the entity goes
        async_remove_entity(hass, entry, "datetime", PlcClock.entity_description.key)
    entry.runtime_data.points.async_setup_platform("datetime", point_datetime, async_add_entities)


class PlcDateTime(PlcPointEntity, DateTimeEntity):
    """A date and time point; the client sends it in the PLC's time zone."""

    entity_description: PlcDateTimeDescription

    @property
    def native_value(self) -> datetime | None:
        """Return the point's date and time (timezone-aware)."""
        value = self.raw_value
        return value if isinstance(value, datetime) else None

    async def async_set_value(self, value: datetime) -> None:
        """Write the date and time."""
        await self.async_write(value)


class PlcClock(PlcEntity, DateTimeEntity):
    """The PLC clock as last read (vendors read it at their own pace); setting it sets the PLC."""

    entity_description = DateTimeEntityDescription(
        key="plc_clock",
        translation_key="plc_clock",
        entity_category=EntityCategory.CONFIG,
        # Its state changes at every clock read (8,600 recorder rows a day on an S7-200
        # SMART): off by default; the clock drift sensor shows how far off the clock is.
        entity_registry_enabled_default=False,
    )

    def __init__(self, entry: PlcBridgeConfigEntry) -> None:
        """Bind the clock to the PLC's device."""
        super().__init__(entry, self.entity_description.key)

    @property
    def native_value(self) -> datetime | None:
        """Return the PLC time the last read reported."""
        return self.coordinator.data.status.clock

    def observed(self) -> datetime | None:
        """The clock as last read."""
        return self.native_value

    async def async_set_value(self, value: datetime) -> None:
        """Set the PLC clock, as the sync_clock action does: for administrators only."""
        # Entity actions have no admin rule of their own: check the calling user as
        # async_register_admin_service does (no user: an automation or the system).
        if self._context is not None and (user_id := self._context.user_id):
            user = await self.hass.auth.async_get_user(user_id)
            if user is None:
                raise UnknownUser(context=self._context, user_id=user_id)
            if not user.is_admin:
                raise Unauthorized(context=self._context, user_id=user_id)
        await self.coordinator.async_set_clock(value)
