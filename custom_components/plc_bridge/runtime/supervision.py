"""Command/feedback supervision: the state read must follow a command within a set time.

An entity with a state and a command (a switch with both, a light, a fan, a climate's on/off)
may carry a `supervision` time, 1-600 s, stored on each of its parts; a cover's or valve's
travel time is its supervision time for open and close. After a command the entity watches
what it reads: when the state has not followed once the time is up, the event
EVENT_FEEDBACK_TIMEOUT is fired (entity_id, name, commanded, state read, seconds) and a repair
issue names the entity ("Pump did not switch on within 10 s"). The first poll that reads the
state following clears the issue and fires EVENT_FEEDBACK_RESTORED (entity_id, name,
commanded, state): two event types, so an automation triggers on the one it wants. A new
command replaces the one watched (its issue stays until the new one is followed or times out);
a stop or a position written ends the watch and withdraws its issue. Supervision never writes.

The issue is persistent and remembers what was commanded, so one left from before a restart
or reload is cleared by the first poll that reads the state following (or withdrawn at start
when the entity no longer has a supervision time). Unload and reload cancel pending timers.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from datetime import datetime
import math
from typing import Any, Final

from homeassistant.config_entries import ConfigEntry
from homeassistant.core import CALLBACK_TYPE, HassJob, HomeAssistant, callback
from homeassistant.helpers import issue_registry as ir
from homeassistant.helpers.entity import Entity
from homeassistant.helpers.event import async_call_later

from ..const import DOMAIN, LOGGER
from .issues import FEEDBACK_TIMEOUT

EVENT_FEEDBACK_TIMEOUT: Final = f"{DOMAIN}_feedback_timeout"
EVENT_FEEDBACK_RESTORED: Final = f"{DOMAIN}_feedback_restored"
COMMANDS = ("on", "off", "open", "close")
"""What an entity may be commanded to do; each has its issue text `feedback_<command>`."""

type Follows = Callable[[str], bool | None]
"""Whether the state read follows a command; None while it cannot be told."""


def seconds_of(stored: Iterable[float | None]) -> float | None:
    """Return the first of the parts' stored times that is one (supervision, travel), else None."""
    for value in stored:
        if value is not None and math.isfinite(seconds := float(value)) and seconds > 0:
            return seconds
    return None


class Supervisor:
    """Watches that one entity's state follows its last command; raises and clears its issue."""

    def __init__(
        self,
        entry: ConfigEntry[Any],
        key: str,
        name: str,
        seconds: float | None,
        follows: Follows,
    ) -> None:
        """Remember the entity's entry, key, name (for messages) and supervision time."""
        self._entry = entry
        self.issue_id = f"{FEEDBACK_TIMEOUT}_{entry.entry_id}_{key}"
        self._name = name
        self.seconds = seconds
        self._follows = follows
        self._entity: Entity | None = None
        self._commanded: str | None = None
        self._faulted = False
        self._timer: CALLBACK_TYPE | None = None

    @callback
    def async_attach(self, entity: Entity) -> CALLBACK_TYPE:
        """Start with the entity: take over an issue left from before; return the detach."""
        self._entity = entity
        issue = ir.async_get(entity.hass).async_get_issue(DOMAIN, self.issue_id)
        commanded = (issue.data or {}).get("commanded") if issue is not None else None
        if issue is not None and (self.seconds is None or commanded not in COMMANDS):
            ir.async_delete_issue(entity.hass, DOMAIN, self.issue_id)
        elif issue is not None:
            self._commanded, self._faulted = str(commanded), True
        return self._cancel

    @callback
    def watch(self, commanded: str | None) -> None:
        """A command was sent: watch its state (None: nothing to follow, its issue withdrawn)."""
        self._cancel()
        if self.seconds is None or self._entity is None:
            return
        if commanded is None:
            self._commanded = None
            if self._faulted:
                self._faulted = False
                ir.async_delete_issue(self._entity.hass, DOMAIN, self.issue_id)
            return
        self._commanded = commanded  # judged by the polls after it: a read-back may be stale
        self._timer = async_call_later(
            self._entity.hass, self.seconds, HassJob(self._timeout, cancel_on_shutdown=True)
        )

    @callback
    def update(self) -> None:
        """A poll answered: the state followed the command watched, or not yet."""
        if self._commanded is not None and self._follows(self._commanded):
            self._settled()

    @callback
    def _timeout(self, _now: datetime) -> None:
        """The time is up: raise the fault unless the state followed."""
        self._timer = None
        if self._commanded is None or self._entity is None:
            return
        if self._follows(self._commanded):
            self._settled()
            return
        self._raise(self._entity.hass, self._entity, self._commanded)

    def _raise(self, hass: HomeAssistant, entity: Entity, commanded: str) -> None:
        """Fire the timeout event and raise the issue that names the entity and its command."""
        assert self.seconds is not None  # a timer runs only with a supervision time
        seconds = f"{self.seconds:g}"
        if not self._faulted:
            LOGGER.warning(
                "%s did not follow its command (%s) within %s s", self._name, commanded, seconds
            )
        self._faulted = True
        hass.bus.async_fire(
            EVENT_FEEDBACK_TIMEOUT,
            {
                "entity_id": entity.entity_id,
                "name": self._name,
                "commanded": commanded,
                "state": entity.state,
                "seconds": self.seconds,
            },
        )
        ir.async_create_issue(
            hass,
            DOMAIN,
            self.issue_id,
            is_fixable=False,
            is_persistent=True,  # cleared by a poll after a restart, not dropped by it
            severity=ir.IssueSeverity.WARNING,
            translation_key=f"feedback_{commanded}",
            translation_placeholders={
                "name": self._name,
                "title": self._entry.title,
                "seconds": seconds,
            },
            data={"entry_id": self._entry.entry_id, "commanded": commanded},
        )

    @callback
    def _settled(self) -> None:
        """The state follows: stop watching; a raised fault is cleared and said so."""
        self._cancel()
        commanded, self._commanded = self._commanded, None
        if not self._faulted or self._entity is None:
            return
        self._faulted = False
        LOGGER.info("%s follows its command (%s) again", self._name, commanded)
        hass = self._entity.hass
        ir.async_delete_issue(hass, DOMAIN, self.issue_id)
        hass.bus.async_fire(
            EVENT_FEEDBACK_RESTORED,
            {
                "entity_id": self._entity.entity_id,
                "name": self._name,
                "commanded": commanded,
                "state": self._entity.state,
            },
        )

    @callback
    def _cancel(self) -> None:
        """Forget a pending timer."""
        if self._timer is not None:
            self._timer()
            self._timer = None
