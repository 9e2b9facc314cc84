"""Buttons: pressing writes a point's "on" value once, or pulses it on, then off.

Without a pulse duration (the safe mode) a press writes the "on" value and the PLC program
resets the bit. With one (0.1-60 s) the "off" value follows after that time, timed by Home
Assistant; a failed off-write is tried once more, then logged and raised as a repair issue.
Unloading the entry or stopping Home Assistant mid-pulse sends the pending off-write at once
(while the PLC can still be reached); a Home Assistant that dies leaves the "on" value set.
"""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime
from typing import Any

from homeassistant.components.button import ButtonEntity, ButtonEntityDescription
from homeassistant.const import EVENT_HOMEASSISTANT_STOP
from homeassistant.core import CALLBACK_TYPE, Event, HassJob, HomeAssistant
from homeassistant.exceptions import HomeAssistantError
from homeassistant.helpers import issue_registry as ir
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback
from homeassistant.helpers.event import async_call_later

from .const import CONF_PULSE, DOMAIN, LOGGER, PULSE_MAX, PULSE_MIN
from .coordinator import PlcBridgeConfigEntry
from .entity import PlcPointDescription, PlcPointEntity, point_fields
from .plc import ValueKind
from .points import PointConfig

PARALLEL_UPDATES = 1
PULSE_FAILED = "pulse_failed"


@dataclass(frozen=True, kw_only=True)
class PlcButtonDescription(ButtonEntityDescription, PlcPointDescription):
    """A point written by a button: `pulse` seconds on, or 0 for a single write."""

    pulse: float = 0.0


def point_button(entry: PlcBridgeConfigEntry, config: PointConfig) -> PlcButton:
    """Return the button of a point."""
    pulse = float(config.data.get(CONF_PULSE) or 0.0)
    pulse = min(max(pulse, PULSE_MIN), PULSE_MAX) if pulse else 0.0
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
        self._timer: CALLBACK_TYPE | None = None
        self._unlisten: CALLBACK_TYPE | None = None

    def observed(self) -> Any:
        """A button shows no value: only its availability changes its state."""
        return None

    def _level(self, *, on: bool) -> bool | int | float:
        """Return the raw value that means on or off for this point."""
        description = self.entity_description
        return description.convert.state_value(on, boolean=description.kind is ValueKind.BOOL)

    async def async_press(self) -> None:
        """Write "on"; with a pulse, write "off" when it ends (a new press restarts it)."""
        self._cancel()
        await self.async_write(self._level(on=True))
        if self.entity_description.pulse > 0:
            self._timer = async_call_later(
                self.hass, self.entity_description.pulse, HassJob(self._async_pulse_ended)
            )
            self._unlisten = self.hass.bus.async_listen_once(
                EVENT_HOMEASSISTANT_STOP, self._async_stopping
            )

    def _cancel(self) -> bool:
        """Forget the pending end of a pulse; True when one was pending."""
        pending = self._timer is not None
        for cancel in (self._timer, self._unlisten):
            if cancel is not None:
                cancel()
        self._timer = self._unlisten = None
        return pending

    async def _async_pulse_ended(self, _now: datetime) -> None:
        """End the pulse when its time is up."""
        self._timer = None
        await self._async_write_off()

    async def _async_stopping(self, _event: Event) -> None:
        """Home Assistant stops mid-pulse: end the pulse now."""
        self._unlisten = None
        if self._cancel():
            await self._async_write_off()

    async def async_will_remove_from_hass(self) -> None:
        """Removed (unload, reload, edit) mid-pulse: end the pulse now."""
        if self._cancel():
            await self._async_write_off()
        await super().async_will_remove_from_hass()

    async def _async_write_off(self) -> None:
        """Write "off", once more if that fails; then log it and raise a repair issue."""
        self._cancel()
        entry = self.coordinator.config_entry
        issue = f"{PULSE_FAILED}_{entry.entry_id}_{self.entity_description.key}"
        error: HomeAssistantError | None = None
        for _ in range(2):
            try:
                await self.async_write(self._level(on=False))
            except HomeAssistantError as err:
                error = err
                continue
            ir.async_delete_issue(self.hass, DOMAIN, issue)
            return
        address = self.entity_description.point.address
        LOGGER.error("%s: the pulse on %s did not end: %s", self.name, address, error)
        ir.async_create_issue(
            self.hass,
            DOMAIN,
            issue,
            is_fixable=False,
            severity=ir.IssueSeverity.ERROR,
            translation_key=PULSE_FAILED,
            translation_placeholders={
                "title": entry.title,
                "point": str(self.entity_description.name),
                "address": address,
                "error": str(error),
            },
        )
