"""Outputs Home Assistant switches on and always releases: a pulse, a cover's level command.

An output is held from its "on" write until its "off" is confirmed. The off is due when the
hold ends (a pulse's time, a travel time, the end position: the entity decides), whatever the
outcome of the on-write (a timeout may hide an on that landed). An off the PLC does not confirm
is tried again with back-off (1 s, doubling, at most every RETRY_MAX s) for as long as the entry
is loaded; meanwhile a repair issue names the output, and it is cleared once the off is
written. Unload, reload, removal of the entity and Home Assistant's stop write the off at once
(one try: the connection closes next). A command for an output already held and confirmed
keeps it as it is: a second press during a pulse keeps the first pulse's end.
"""

from __future__ import annotations

import asyncio
from collections.abc import Awaitable, Callable, Mapping
from contextlib import nullcontext
from datetime import datetime
from enum import Enum, auto
from typing import Any, Protocol

from homeassistant.config_entries import ConfigEntry
from homeassistant.const import EVENT_HOMEASSISTANT_STOP
from homeassistant.core import CALLBACK_TYPE, Event, HassJob, HomeAssistant, callback
from homeassistant.exceptions import HomeAssistantError, ServiceValidationError
from homeassistant.helpers import issue_registry as ir
from homeassistant.helpers.event import async_call_later

from ..const import DOMAIN, LOGGER
from ..plc import Point, PointResult, Value, urgent
from .errors import named

RETRY_FIRST = 1.0
"""Seconds before an off-write the PLC did not confirm is tried again (then doubling)."""
RETRY_MAX = 10.0
"""The longest wait between two tries of an off-write."""


class State(Enum):
    """Where an output stands."""

    IDLE = auto()
    HELD = auto()
    RELEASING = auto()


class Writer(Protocol):
    """What an output writes through: the coordinator's one guarded write path."""

    async def async_write_values(
        self, values: Mapping[Point, Value]
    ) -> Mapping[Point, PointResult]:
        """Write the values in one request; return each point's result."""


async def async_send(coordinator: Writer, values: Mapping[Point, Value], *, release: bool) -> None:
    """Write in one request, urgently where it releases an output; raise for a refused point.

    No read-back here: an output's timing never waits for a poll.
    """
    with urgent() if release else nullcontext():
        results = await coordinator.async_write_values(values)
    failed = [named(point, result.error) for point, result in results.items() if result.error]
    if failed:
        raise HomeAssistantError(
            translation_domain=DOMAIN,
            translation_key="write_failed",
            translation_placeholders={"error": "; ".join(failed)},
        )


class Output:
    """One output Home Assistant turns on and releases, and the repair issue while it cannot."""

    def __init__(
        self,
        entry: ConfigEntry[Any],
        lock: asyncio.Lock,
        issue: tuple[str, str],
        *,
        name: str,
        address: str,
        write_off: Callable[[], Awaitable[None]],
        read_back: Callable[[], None],
    ) -> None:
        """Remember the output; `issue` is (translation key, item key); `lock` orders writes."""
        self._entry = entry
        self._lock = lock
        self._kind, key = issue
        self.issue_id = f"{self._kind}_{entry.entry_id}_{key}"
        self.name = name
        self._address = address
        self._write_off = write_off
        self._read_back = read_back
        self._hass: HomeAssistant | None = None
        self._state = State.IDLE
        self._confirmed = False  # the on-write of the hold was confirmed
        self._generation = 0  # changes with each hold and release: a stale release stands down
        self._failures = 0
        self._timer: CALLBACK_TYPE | None = None

    @property
    def held(self) -> bool:
        """True from the on-write until the off is due."""
        return self._state is State.HELD

    @property
    def releasing(self) -> bool:
        """True while the off is due and not confirmed."""
        return self._state is State.RELEASING

    @callback
    def async_attach(self, hass: HomeAssistant) -> CALLBACK_TYPE:
        """Follow Home Assistant's stop; release what a previous setup could not. Return unsub."""
        self._hass = hass
        unsub = hass.bus.async_listen(EVENT_HOMEASSISTANT_STOP, self._async_stopping)
        if ir.async_get(hass).async_get_issue(DOMAIN, self.issue_id) is not None:
            self._failures = 1  # the issue stands for the failure of the last setup
            self._state = State.RELEASING
            self._spawn()
        return unsub

    async def async_turn_on(
        self, write_on: Callable[[], Awaitable[None]], seconds: float, *, again: bool = False
    ) -> bool:
        """Write "on" and release after `seconds` whatever its outcome; False: kept as it was.

        A second command while held keeps the hold's end: nothing is written once the on is
        confirmed, unless `again` (a level written again); one while the off is not confirmed
        is refused. Nothing was sent when the write raises ServiceValidationError, so nothing
        is held then.
        """
        async with self._lock:
            if self._state is State.RELEASING:
                raise HomeAssistantError(
                    translation_domain=DOMAIN,
                    translation_key="output_not_released",
                    translation_placeholders={"name": self.name, "address": self._address},
                )
            if self._state is State.HELD and self._confirmed and not again:
                return False
            first = self._state is State.IDLE
            if first:
                self._generation += 1
                self._state = State.HELD
            try:
                await write_on()
            except ServiceValidationError:
                if first:
                    self._state = State.IDLE
                raise
            except HomeAssistantError:
                if first:
                    self._start(seconds)
                raise
            self._confirmed = True
            if first:
                self._start(seconds)
            return True

    @callback
    def release_soon(self) -> None:
        """Write the off now, in the background (an end position reached, a hold's end)."""
        if self._state is not State.HELD:
            return
        self._cancel_timer()
        self._state = State.RELEASING
        self._spawn()

    @callback
    def released(self) -> None:
        """Another write (an interlock's) wrote the off and the PLC confirmed it."""
        if self._state is State.IDLE:
            return
        self._generation += 1
        self._done()

    @callback
    def unconfirmed(self) -> None:
        """Another write meant to write the off failed: write it again if it is held."""
        self.release_soon()

    async def async_end(self) -> None:
        """Write the off once, now (unload, removal, stop); an issue stays if it fails."""
        async with self._lock:
            if self._state is State.IDLE:
                return
            self._cancel_timer()
            self._generation += 1
            self._state = State.RELEASING
            await self._async_write_off(retry=False)

    @callback
    def _start(self, seconds: float) -> None:
        """Release the output after this many seconds."""
        self._cancel_timer()
        self._timer = async_call_later(self._need_hass(), seconds, HassJob(self._hold_ended))

    @callback
    def _hold_ended(self, _now: datetime) -> None:
        """The hold's time is up."""
        self._timer = None
        self.release_soon()

    @callback
    def _spawn(self) -> None:
        """Write the off in a background task of the entry."""
        self._entry.async_create_background_task(
            self._need_hass(), self._async_release(self._generation), f"release {self.name}"
        )

    async def _async_release(self, generation: int) -> None:
        """Write the off unless a newer command or release took over meanwhile."""
        async with self._lock:
            if generation != self._generation or self._state is not State.RELEASING:
                return
            written = await self._async_write_off(retry=True)
        if written:
            self._read_back()

    async def _async_write_off(self, *, retry: bool) -> bool:
        """Write the off; on failure raise the issue and, with `retry`, try again later."""
        try:
            await self._write_off()
        except HomeAssistantError as err:
            self._failed(err)
            if retry:
                delay = min(RETRY_FIRST * 2 ** (self._failures - 1), RETRY_MAX)
                self._timer = async_call_later(self._need_hass(), delay, HassJob(self._retry))
            return False
        self._done()
        return True

    @callback
    def _retry(self, _now: datetime) -> None:
        """Try the off-write again."""
        self._timer = None
        if self._state is State.RELEASING:
            self._spawn()

    @callback
    def _failed(self, err: HomeAssistantError) -> None:
        """Log the first failure and raise the issue that names the output."""
        self._failures += 1
        if self._failures > 1:
            LOGGER.debug("%s: %s is still not released: %s", self.name, self._address, err)
            return
        LOGGER.error(
            "%s: %s could not be released, trying again until it is: %s",
            self.name,
            self._address,
            err,
        )
        ir.async_create_issue(
            self._need_hass(),
            DOMAIN,
            self.issue_id,
            is_fixable=False,
            severity=ir.IssueSeverity.ERROR,
            translation_key=self._kind,
            translation_placeholders={
                "title": self._entry.title,
                "point": self.name,
                "address": self._address,
                "error": str(err),
            },
            data={"entry_id": self._entry.entry_id},
        )

    @callback
    def _done(self) -> None:
        """The off is confirmed: nothing is pending, the issue goes."""
        self._cancel_timer()
        self._state = State.IDLE
        self._confirmed = False
        if self._failures:
            LOGGER.info("%s: %s is released", self.name, self._address)
            self._failures = 0
        if self._hass is not None:
            ir.async_delete_issue(self._hass, DOMAIN, self.issue_id)

    async def _async_stopping(self, _event: Event) -> None:
        """Home Assistant stops: write the off now."""
        await self.async_end()

    @callback
    def _cancel_timer(self) -> None:
        """Forget a pending hold's end or retry."""
        if self._timer is not None:
            self._timer()
            self._timer = None

    def _need_hass(self) -> HomeAssistant:
        """Home Assistant, known once the entity is added."""
        assert self._hass is not None  # attached when the entity was added
        return self._hass
