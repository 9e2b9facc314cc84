"""The logbook names an alarm word's alarm: `Overheat: Raised`, on the alarm word's entity."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from homeassistant.components.logbook.const import (
    LOGBOOK_ENTRY_ENTITY_ID,
    LOGBOOK_ENTRY_MESSAGE,
    LOGBOOK_ENTRY_NAME,
)
from homeassistant.const import ATTR_ENTITY_ID
from homeassistant.core import Event, HomeAssistant, callback
from homeassistant.helpers.translation import async_get_cached_translations

from .const import DOMAIN, EVENT_ALARM

CHANGE_TEXT = f"component.{DOMAIN}.entity.event.alarm_word.state_attributes.event_type.state."
"""Where the words for a bit's change (raised, cleared) are in the entity translations."""


@callback
def async_describe_events(
    hass: HomeAssistant,
    async_describe_event: Callable[[str, str, Callable[[Event], dict[str, Any]]], None],
) -> None:
    """Describe the alarm events for the logbook."""

    @callback
    def describe(event: Event) -> dict[str, Any]:
        """Return the alarm's name and change, in Home Assistant's language, on its entity."""
        change = str(event.data.get("change", ""))
        texts = async_get_cached_translations(hass, hass.config.language, "entity", DOMAIN)
        return {
            LOGBOOK_ENTRY_NAME: str(event.data.get("name", "")),
            LOGBOOK_ENTRY_MESSAGE: texts.get(f"{CHANGE_TEXT}{change}", change),
            LOGBOOK_ENTRY_ENTITY_ID: event.data.get(ATTR_ENTITY_ID),
        }

    async_describe_event(DOMAIN, EVENT_ALARM, describe)
