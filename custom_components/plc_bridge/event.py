"""Events: an alarm or status word fires `<bit's name> raised` / `cleared` as its bits change.

The event type names the alarm, so that an automation's event trigger says which one: `Overheat
raised`; the event data carries the bit, its name and the change. The same change is fired on
the bus as `plc_bridge_alarm`, which the logbook describes (logbook.py): the frontend's logbook
shows an event entity's change without its type.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from homeassistant.components.event import EventEntity, EventEntityDescription
from homeassistant.const import ATTR_ENTITY_ID
from homeassistant.core import HomeAssistant, callback
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from .const import EVENT_ALARM
from .coordinator import PlcBridgeConfigEntry
from .entity import PlcPointDescription, PlcPointEntity, point_fields
from .model.alarm import bit_set, word_bits
from .model.points import PointConfig

PARALLEL_UPDATES = 0
RAISED = "raised"
CLEARED = "cleared"


@dataclass(frozen=True, kw_only=True)
class PlcEventDescription(EventEntityDescription, PlcPointDescription):
    """An alarm word shown as an event entity."""

    bits: tuple[tuple[int, str], ...] = ()


def event_type(label: str, change: str) -> str:
    """Return the event type of a named bit's change: `Overheat raised`."""
    return f"{label} {change}"


def point_event(entry: PlcBridgeConfigEntry, config: PointConfig) -> PlcAlarmEvent:
    """Return the event entity of an alarm word: two event types per named bit."""
    bits = word_bits(config)
    types = [event_type(label, change) for _, label in bits for change in (RAISED, CLEARED)]
    description = PlcEventDescription(
        **point_fields(entry, config),
        translation_key="alarm_word",
        event_types=types or [RAISED, CLEARED],  # a word without names fires nothing
        bits=bits,
    )
    return PlcAlarmEvent(entry, config, description)


async def async_setup_entry(
    hass: HomeAssistant,
    entry: PlcBridgeConfigEntry,
    async_add_entities: AddConfigEntryEntitiesCallback,
) -> None:
    """Add an event entity for each alarm word."""
    entry.runtime_data.points.async_setup_platform("event", point_event, async_add_entities)


class PlcAlarmEvent(PlcPointEntity, EventEntity):
    """Fires when a named bit of the word is set (`<name> raised`) or reset (`<name> cleared`).

    The first value read is the baseline: bits already set when Home Assistant starts fire
    nothing. A failed read keeps the baseline, so a bit that changed meanwhile fires after.
    """

    entity_description: PlcEventDescription
    _restores = False  # its last event, restored by Home Assistant's event entity
    _last: int | None = None

    async def async_added_to_hass(self) -> None:
        """Take the word as read now as the baseline."""
        await super().async_added_to_hass()
        self._last = self._word()

    def _word(self) -> int | None:
        """Return the word of the last poll as an integer, None when it did not read."""
        raw = self.raw_value
        return raw if isinstance(raw, int) and not isinstance(raw, bool) else None

    def observed(self) -> Any:
        """Only availability writes the state; events write their own."""
        return None

    @callback
    def _handle_coordinator_update(self) -> None:
        """Fire an event for each named bit that changed since the last word read."""
        word = self._word()
        if word is not None and self._last is not None and self.available:
            for bit, label in self.entity_description.bits:
                now, before = bit_set(word, bit), bit_set(self._last, bit)
                if now != before:
                    change = RAISED if now else CLEARED
                    data = {"bit": bit, "name": label, "change": change}
                    self._trigger_event(event_type(label, change), data)
                    self.hass.bus.async_fire(EVENT_ALARM, {ATTR_ENTITY_ID: self.entity_id, **data})
                    self.async_write_ha_state()
        if word is not None:
            self._last = word
        super()._handle_coordinator_update()
