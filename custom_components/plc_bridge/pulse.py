"""A pulse on one point: "on" written now, "off" after its time, timed by Home Assistant.

Used by buttons and by the commands of entities of several points. A failed off-write is
tried once more, then logged and raised as a repair issue (the next pulse that ends clears
it). Unloading the entry or stopping Home Assistant mid-pulse sends the pending off-write at
once (while the PLC can still be reached); a Home Assistant that dies leaves "on" set.
"""

from __future__ import annotations

from collections.abc import Awaitable, Callable, Mapping
from datetime import datetime
from typing import Any

from homeassistant.const import EVENT_HOMEASSISTANT_STOP
from homeassistant.core import CALLBACK_TYPE, Event, HassJob, HomeAssistant
from homeassistant.exceptions import HomeAssistantError
from homeassistant.helpers import issue_registry as ir
from homeassistant.helpers.event import async_call_later

from .const import CONF_PULSE, DOMAIN, LOGGER, PULSE_MAX, PULSE_MIN
from .models import PlcBridgeConfigEntry

PULSE_FAILED = "pulse_failed"


def pulse_seconds(data: Mapping[str, Any]) -> float:
    """Return a point's pulse in seconds, kept within 0.1-60; 0 for a single write."""
    pulse = float(data.get(CONF_PULSE) or 0.0)
    return min(max(pulse, PULSE_MIN), PULSE_MAX) if pulse else 0.0


class Pulse:
    """The pending end of a pulse on one point, and how it is ended."""

    def __init__(
        self,
        entry: PlcBridgeConfigEntry,
        key: str,
        *,
        name: str,
        address: str,
        write_off: Callable[[], Awaitable[None]],
    ) -> None:
        """Remember the point (`key`: what names its repair issue) and its off-write."""
        self._entry = entry
        self._issue = f"{PULSE_FAILED}_{entry.entry_id}_{key}"
        self._name = name
        self._address = address
        self._write_off = write_off
        self._timer: CALLBACK_TYPE | None = None
        self._unlisten: CALLBACK_TYPE | None = None
        self._hass: HomeAssistant | None = None

    def start(self, hass: HomeAssistant, seconds: float) -> None:
        """Write "off" after this many seconds ("on" is written already)."""
        self.cancel()
        self._hass = hass
        self._timer = async_call_later(hass, seconds, HassJob(self._async_ended))
        self._unlisten = hass.bus.async_listen_once(EVENT_HOMEASSISTANT_STOP, self._async_stopping)

    def cancel(self) -> bool:
        """Forget the pending end; True when one was pending."""
        pending = self._timer is not None
        for cancel in (self._timer, self._unlisten):
            if cancel is not None:
                cancel()
        self._timer = self._unlisten = None
        return pending

    async def async_end_now(self) -> None:
        """End a pending pulse at once (its entity is removed)."""
        if self.cancel():
            await self._async_write_off()

    async def _async_ended(self, _now: datetime) -> None:
        """End the pulse when its time is up."""
        self._timer = None
        await self._async_write_off()

    async def _async_stopping(self, _event: Event) -> None:
        """Home Assistant stops mid-pulse: end the pulse now."""
        self._unlisten = None
        await self.async_end_now()

    async def _async_write_off(self) -> None:
        """Write "off", once more if that fails; then log it and raise a repair issue."""
        self.cancel()
        hass = self._hass
        assert hass is not None  # set when the pulse started
        error: HomeAssistantError | None = None
        for _ in range(2):
            try:
                await self._write_off()
            except HomeAssistantError as err:
                error = err
                continue
            ir.async_delete_issue(hass, DOMAIN, self._issue)
            return
        LOGGER.error("%s: the pulse on %s did not end: %s", self._name, self._address, error)
        ir.async_create_issue(
            hass,
            DOMAIN,
            self._issue,
            is_fixable=False,
            severity=ir.IssueSeverity.ERROR,
            translation_key=PULSE_FAILED,
            translation_placeholders={
                "title": self._entry.title,
                "point": self._name,
                "address": self._address,
                "error": str(error),
            },
        )
