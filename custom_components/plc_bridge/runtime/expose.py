"""Exposes at run time: Home Assistant states written to the PLC, batched, paced, watched.

Each expose follows its entity. A new value is written at once unless the expose wrote less
than its cooldown ago: then the latest value goes when the cooldown ends. Every value that
becomes due within BATCH_WINDOW goes out in one write of the coordinator (the checks every
write passes), which the vendor packs into its fewest requests. A periodic resend writes the
last value again; send-on-start writes the current states once Home Assistant has started,
after every setup of the entry. An expose whose sending is off (pasted from a file, until the
user turns it on in its form) is not followed at all: it writes nothing, not even at start.
A value that cannot be written is logged once and not sent; a failing write is logged once
(and once when it works again), and after FAILURE_LIMIT failures in a row raises a repair
issue naming the expose, cleared by its next write that works. A value that failed is not
lost: every RETRY_INTERVAL the values that failed go out again, in one write.
"""

from __future__ import annotations

from datetime import datetime, timedelta
from functools import partial
from typing import Any

from homeassistant.config_entries import ConfigEntry
from homeassistant.const import CONF_ENTITY_ID
from homeassistant.core import (
    CALLBACK_TYPE,
    Event,
    EventStateChangedData,
    HassJob,
    HomeAssistant,
    State,
    callback,
)
from homeassistant.exceptions import HomeAssistantError
from homeassistant.helpers import entity_registry as er, issue_registry as ir
from homeassistant.helpers.event import (
    async_call_later,
    async_track_state_change_event,
    async_track_time_interval,
)
from homeassistant.helpers.start import async_at_started

from ..const import (
    DOMAIN,
    LOGGER,
    SUBENTRY_EXPOSE,
)
from ..model.expose import ExposeConfig, entry_exposes, expose_title
from ..plc import PlcError, Point, Value
from .issues import async_clear_expose_issues, async_raise_expose_issue, expose_issue_id

BATCH_WINDOW = 0.1
"""Seconds over which the values that become due are gathered into one write."""
FAILURE_LIMIT = 3
"""Failed writes in a row of one expose that raise its repair issue."""
RETRY_INTERVAL = 30.0
"""Seconds after a failed write before the values that failed are written again."""


def sending(configs: dict[str, ExposeConfig]) -> dict[str, ExposeConfig]:
    """Return the exposes that send: one pasted from a file writes nothing until turned on."""
    return {subentry_id: config for subentry_id, config in configs.items() if config.send}


class PlcExposes:
    """The exposes of one loaded PLC entry, kept in step with its expose subentries."""

    def __init__(self, hass: HomeAssistant, entry: ConfigEntry[Any]) -> None:
        """Bind to the entry; nothing is followed until `async_start`."""
        self._hass = hass
        self._entry = entry
        self._exposes: dict[str, Expose] = {}
        self._batch: dict[str, Expose] = {}
        self._flush: CALLBACK_TYPE | None = None
        self._retry: CALLBACK_TYPE | None = None
        self._writing = False  # a write is on the way: the batch waits for its end

    @callback
    def async_start(self) -> None:
        """Follow every expose; send the current states once Home Assistant has started."""
        unreadable: list[str] = []
        for config in sending(entry_exposes(self._entry, unreadable)).values():
            self._start(config)
        for why in unreadable:
            LOGGER.warning("%s: an expose is left out: %s", self._entry.title, why)
        async_clear_expose_issues(self._hass, self._entry, keep=self._exposes)
        self._entry.async_on_unload(async_at_started(self._hass, self._send_on_start))
        self._entry.async_on_unload(self._entry.add_update_listener(self._async_entry_updated))
        self._entry.async_on_unload(async_follow_renames(self._hass, self._entry))
        self._entry.async_on_unload(self.async_stop)

    @callback
    def async_stop(self) -> None:
        """Stop every expose; values not written yet are dropped."""
        for expose in self._exposes.values():
            expose.stop()
        self._exposes, self._batch = {}, {}
        for timer in (self._flush, self._retry):
            if timer is not None:
                timer()
        self._flush = self._retry = None

    def _start(self, config: ExposeConfig) -> Expose:
        """Follow one expose's entity (and resend its value periodically, if it asks)."""
        expose = self._exposes[config.subentry_id] = Expose(config)
        # An issue raised before a reload or an edit goes at this expose's first write that works.
        issue = expose_issue_id(self._entry, config.subentry_id)
        expose.issue = ir.async_get(self._hass).async_get_issue(DOMAIN, issue) is not None
        expose.unsubscribe.append(
            async_track_state_change_event(
                self._hass, [config.entity_id], partial(self._state_changed, expose)
            )
        )
        if config.resend:
            expose.unsubscribe.append(
                async_track_time_interval(
                    self._hass,
                    partial(self._resend, expose),
                    timedelta(seconds=config.resend),
                    name=f"{self._entry.title} {config.title} resend",
                )
            )
        return expose

    @callback
    def _send_on_start(self, _hass: HomeAssistant) -> None:
        """Write the current state of every expose that asks for it."""
        for expose in self._exposes.values():
            if expose.config.send_on_start:
                self._follow(expose, self._hass.states.get(expose.config.entity_id), again=True)

    async def _async_entry_updated(self, hass: HomeAssistant, entry: ConfigEntry[Any]) -> None:
        """Follow added, edited and removed exposes; an unchanged one goes on as it was."""
        configs = sending(entry_exposes(entry))
        for subentry_id, expose in list(self._exposes.items()):
            if configs.get(subentry_id) != expose.config:
                expose.stop()
                del self._exposes[subentry_id]
                self._batch.pop(subentry_id, None)
        for subentry_id, config in configs.items():
            if subentry_id not in self._exposes:
                expose = self._start(config)
                if config.send_on_start and hass.is_running:
                    self._follow(expose, hass.states.get(config.entity_id), again=True)
        async_clear_expose_issues(hass, entry, keep=configs)

    @callback
    def _state_changed(self, expose: Expose, event: Event[EventStateChangedData]) -> None:
        """Take the entity's new state."""
        self._follow(expose, event.data["new_state"])

    @callback
    def _resend(self, expose: Expose, _now: datetime) -> None:
        """Write the last value again (none yet: nothing)."""
        if expose.value is not None:
            self._queue(expose, again=True)

    @callback
    def _retry_failed(self, _now: datetime) -> None:
        """Write again the values whose write failed (unless the entity has none now)."""
        self._retry = None
        for expose in self._exposes.values():
            if expose.failures and expose.value is not None:
                self._queue(expose, again=False)

    @callback
    def _follow(self, expose: Expose, state: State | None, *, again: bool = False) -> None:
        """Convert a state; queue its value, or log once that it cannot be written."""
        config = expose.config
        source: Any = config.source(state)
        if source is None:  # unavailable or unknown, and no default: nothing is written
            expose.value = None  # nor resent, nor written when a cooldown ends
            return
        try:
            value = config.plc_value(self._entry.runtime_data.client, source)
        except PlcError as err:  # a value the address cannot hold, or an address from a file
            expose.value = None  # an older value pending or resent would not be the entity's
            if not expose.refused:
                expose.refused = True
                LOGGER.warning(
                    "%s: %s: %r cannot be written to %s, nothing sent: %s",
                    self._entry.title,
                    expose.name,
                    source,
                    config.point.address,
                    err,
                )
            return
        expose.refused = False
        expose.value = value
        self._queue(expose, again=again)

    @callback
    def _queue(self, expose: Expose, *, again: bool) -> None:
        """Write the expose's value with the next batch, or when its cooldown ends."""
        expose.again |= again
        if expose.timer is not None:
            return  # the cooldown's end writes the latest value
        now = self._hass.loop.time()
        if expose.sent_at is not None and expose.sent_at + expose.config.cooldown > now:
            wait = expose.sent_at + expose.config.cooldown - now
            expose.timer = async_call_later(
                self._hass, wait, HassJob(partial(self._cooled, expose), cancel_on_shutdown=True)
            )
            return
        self._add(expose)

    @callback
    def _cooled(self, expose: Expose, _now: datetime) -> None:
        """The cooldown ended: write the latest value."""
        expose.timer = None
        self._add(expose)

    @callback
    def _add(self, expose: Expose) -> None:
        """Put the expose into the batch (unless the PLC holds its value and none is asked)."""
        if expose.value == expose.sent and not expose.again:
            return
        if self._hass.is_stopping:  # what is pending is dropped at the stop: so is what follows
            return
        self._batch[expose.config.subentry_id] = expose
        if self._flush is None:
            self._flush = async_call_later(
                self._hass, BATCH_WINDOW, HassJob(self._flush_due, cancel_on_shutdown=True)
            )

    @callback
    def _flush_due(self, _now: datetime) -> None:
        """Write the batch, unless a write is on the way: the batch then goes when it ends."""
        self._flush = None
        if not self._writing:
            self._write_batch()

    @callback
    def _write_batch(self) -> None:
        """Write the batch in the background (cancelled when the entry unloads)."""
        batch, self._batch = list(self._batch.values()), {}
        self._writing = True
        self._entry.async_create_background_task(
            self._hass, self._async_write(batch), f"{self._entry.title} exposes"
        )

    async def _async_write(self, batch: list[Expose]) -> None:
        """Write a batch; what became due meanwhile follows in one write, never before it.

        One write at a time: a write may take several requests, and an older value sent after
        a newer one would stay in the PLC.
        """
        try:
            await self._async_write_now(batch)
        finally:
            self._writing = False
            if self._batch and self._flush is None and not self._hass.is_stopping:
                self._write_batch()

    async def _async_write_now(self, batch: list[Expose]) -> None:
        """Write the batch's values in one call; note each expose's outcome."""
        coordinator = self._entry.runtime_data.coordinator
        now = self._hass.loop.time()
        values: dict[Point, Value] = {}
        sending: dict[Point, Expose] = {}
        for expose in batch:
            expose.sent_at, expose.again = now, False
            if expose.value is None or not self._running(expose):
                continue
            try:
                coordinator.write_guard.check(expose.config.point)
            except HomeAssistantError as err:
                self._failed(expose, str(err))
                continue
            values[expose.config.point] = expose.value
            sending[expose.config.point] = expose
        if not values:
            return
        try:
            results = await coordinator.async_write_values(values)
        except HomeAssistantError as err:
            for expose in sending.values():
                if self._running(expose):
                    self._failed(expose, str(err))
            return
        for point, expose in sending.items():
            if not self._running(expose):
                continue
            result = results.get(point)
            if result is None or result.error is not None:
                self._failed(expose, str(result.error if result else "no answer for the address"))
            else:
                self._written(expose, values[point])

    def _running(self, expose: Expose) -> bool:
        """False for an expose removed or edited while its write was on the way (no issue then)."""
        return self._exposes.get(expose.config.subentry_id) is expose

    def _written(self, expose: Expose, value: Value) -> None:
        """Note a write the PLC took; say so once after failures, and clear the issue."""
        expose.sent = value
        if expose.failures:
            LOGGER.info("%s: %s is written again", self._entry.title, expose.name)
        expose.failures = 0
        if expose.issue:
            expose.issue = False
            issue = expose_issue_id(self._entry, expose.config.subentry_id)
            ir.async_delete_issue(self._hass, DOMAIN, issue)

    def _failed(self, expose: Expose, error: str) -> None:
        """Note a failed write: logged at the first, an issue after FAILURE_LIMIT in a row."""
        expose.sent = None  # the same value is written again by the retry or the next change
        expose.failures += 1
        if self._retry is None:
            self._retry = async_call_later(
                self._hass, RETRY_INTERVAL, HassJob(self._retry_failed, cancel_on_shutdown=True)
            )
        if expose.failures == 1:
            LOGGER.warning(
                "%s: %s cannot be written to %s: %s",
                self._entry.title,
                expose.name,
                expose.config.point.address,
                error,
            )
        if expose.failures == FAILURE_LIMIT:  # an issue from before takes today's words
            expose.issue = True
            async_raise_expose_issue(
                self._hass,
                self._entry,
                expose.config.subentry_id,
                name=expose.name,
                address=expose.config.point.address,
                error=error,
            )


@callback
def async_start_exposes(hass: HomeAssistant, entry: ConfigEntry[Any]) -> None:
    """Start the entry's exposes; they stop when it unloads."""
    PlcExposes(hass, entry).async_start()


class Expose:
    """One expose running: the value it holds, when it last wrote, and how its writes go."""

    def __init__(self, config: ExposeConfig) -> None:
        """Start with nothing written."""
        self.config = config
        self.value: Value | None = None  # the latest value converted: written, or to be
        self.sent: Value | None = None  # the value the PLC last took
        self.sent_at: float | None = None  # loop time of the last write
        self.again = False  # write the value even if the PLC holds it (start, resend)
        self.timer: CALLBACK_TYPE | None = None  # the end of the cooldown
        self.unsubscribe: list[CALLBACK_TYPE] = []
        self.refused = False  # a value that cannot be written was logged
        self.failures = 0  # failed writes in a row
        self.issue = False

    @property
    def name(self) -> str:
        """What the log and the repair issue call the expose."""
        return self.config.title

    def stop(self) -> None:
        """Stop following the entity and forget a pending write."""
        for unsubscribe in [*self.unsubscribe, self.timer]:
            if unsubscribe is not None:
                unsubscribe()
        self.unsubscribe, self.timer = [], None


@callback
def async_follow_renames(hass: HomeAssistant, entry: ConfigEntry[Any]) -> CALLBACK_TYPE:
    """Keep each expose on its entity when the entity's id is changed in Home Assistant."""

    @callback
    def renamed(event: Event[er.EventEntityRegistryUpdatedData]) -> None:
        """Store the new entity id in the exposes that named the old one."""
        data = event.data
        if data["action"] != "update" or "old_entity_id" not in data:
            return
        for subentry in list(entry.subentries.values()):
            stored = subentry.data
            if subentry.subentry_type != SUBENTRY_EXPOSE:
                continue
            if stored.get(CONF_ENTITY_ID) == data["old_entity_id"]:
                moved = {**stored, CONF_ENTITY_ID: data["entity_id"]}
                hass.config_entries.async_update_subentry(
                    entry, subentry, data=moved, title=expose_title(moved)
                )

    return hass.bus.async_listen(er.EVENT_ENTITY_REGISTRY_UPDATED, renamed)
