"""When a PLC is polled, and which entities hear of it.

Polls start an interval after the previous one started (at once when a slow one ran past it),
a setup waits for a bounded first poll, points added by edits are read once the edits pause,
and after a poll only the entities whose point changed (and the PLC's own) are updated. A poll
reads the points whose poll class is due (poll_classes.py); the others keep their results,
except after a failed poll: the first good one reads every point.

A paced PLC's poll takes a request interval per request: each request's values are shown as it
returns. Points edits added join a poll that is running or due before a read of their own would
end (read first in it), so that no point is read twice over the one paced transport.
"""

from __future__ import annotations

import asyncio
from collections.abc import Callable, Collection, Container, Iterable, Mapping
from dataclasses import replace
import math
from random import randint
from typing import Any, Protocol

from homeassistant.config_entries import ConfigEntry
from homeassistant.core import CALLBACK_TYPE, HassJob, HassJobType, HomeAssistant, callback
from homeassistant.helpers.event import RANDOM_MICROSECOND_MAX, RANDOM_MICROSECOND_MIN
from homeassistant.helpers.update_coordinator import DataUpdateCoordinator

from ..const import LOGGER
from ..model.poll_classes import NORMAL, POLL_CLASSES
from ..plc import PlcClient, PlcError, Point, PointResult, ReadResult

FIRST_POLL_PACING = 1.0
"""Seconds of vendor pacing a setup waits for: a PLC paced slower shows its first points then.

With the S7-200 SMART's connect (three requests a second apart) a start takes about 3 s.
"""
EDIT_DELAY = 1.0
"""Seconds after the last edit before the points edits added are read (in one read)."""
BASE_MEMBERS = ("_schedule_refresh", "_unsub_refresh", "_retry_after", "_listeners")
"""DataUpdateCoordinator's private members the poll cadence relies on (see PollingCoordinator)."""
UPDATE_SLICE = 200
"""Entities a poll updates in one turn of the event loop (a state write costs ~50 µs)."""


def compared(
    before: Mapping[Point, PointResult], after: Mapping[Point, PointResult]
) -> tuple[dict[Point, PointResult], set[Point]]:
    """Return the results of `after`, the unchanged ones as kept from `before`, and what changed.

    A kept result is an object that already survived garbage collections: a quiet poll then
    leaves nothing new behind for the next full collection to walk.
    """
    values: dict[Point, PointResult] = {}
    changes: set[Point] = set()
    for point, result in after.items():
        old = before.get(point)
        if old is not None and old == result:
            values[point] = old
        else:
            values[point] = result
            changes.add(point)
    return values, changes


class Follower(Protocol):
    """An entity the coordinator updates itself, without a listener of its own."""

    @property
    def hass(self) -> HomeAssistant | None:
        """None once Home Assistant aborted adding the entity."""

    def _handle_coordinator_update(self) -> None:
        """Show the coordinator's new data."""


class PollingCoordinator(DataUpdateCoordinator[ReadResult]):
    """Polls `_poll` through `client` from start to start; tells the entities what changed.

    Entities follow with their point (`async_follow`); the PLC's own entities with none. All
    followers share one listener of the base, which starts polling with the first and stops it
    with the last: an entity keeps no callback, closure or remover of its own.

    The cadence needs one override of DataUpdateCoordinator's private scheduler,
    `_schedule_refresh`, and with it the base's members of that contract (BASE_MEMBERS,
    checked on both supported Home Assistant releases by tests/runtime/test_polling_contract.py):
    the handle `_unsub_refresh` the base cancels at shutdown, the `_retry_after` an
    UpdateFailed asks for, and `_listeners`, the base's listeners with their contexts.
    """

    config_entry: ConfigEntry[Any]

    def __init__(self, hass: HomeAssistant, entry: ConfigEntry[Any], client: PlcClient) -> None:
        """Bind the coordinator to the entry and its client; nothing is polled yet."""
        self.client = client
        super().__init__(hass, LOGGER, config_entry=entry, name=entry.title)
        self._poll: list[Point] = []
        self._schedule = PollSchedule()  # which of `_poll` each poll reads (poll classes)
        self._asked: set[Point] = set()  # points the next poll reads whatever their class
        self._started: float | None = None  # loop time the last poll started
        self._base: float | None = None  # loop time the next poll is an interval after
        self._due: float | None = None  # loop time the scheduled poll is due
        self._grid: float | None = None  # the due time of the scheduled poll now running
        self.cycle: float | None = None
        """Seconds from the start of the poll before the last to the start of the last."""
        self._partial = False  # the last poll read only the first points (a paced setup)
        self._again = False  # edited points wait for the poll after the running one: at once
        self._reading = False
        self._lead: frozenset[Point] = frozenset()  # read first in every poll (availability)
        self._changed: set[Point] | None = None  # what the last poll changed (None: all)
        self._edited: set[Point] = set()  # points edits added, not read yet
        self._unsub_edit: CALLBACK_TYPE | None = None
        self._followers: dict[Follower, Point | None] = {}
        self._unsub_followers: CALLBACK_TYPE | None = None
        self._stagger = randint(RANDOM_MICROSECOND_MIN, RANDOM_MICROSECOND_MAX) / 10**6
        """Where in its second each poll starts, as Home Assistant staggers coordinators."""

    @property
    def poll_intervals(self) -> dict[str, float]:
        """Seconds between reads of each poll class that has points."""
        return dict(self._schedule.intervals)

    @property
    def poll_counts(self) -> dict[str, int]:
        """How many points each poll class has."""
        return self._schedule.counts()

    @callback
    def ask_back(self, points: Iterable[Point]) -> None:
        """Have the next poll read these polled points, whatever their poll class."""
        read = self.data.values if self.data is not None else {}
        self._asked.update(point for point in points if point in read)

    async def async_first_poll(self) -> None:
        """Poll before the entities are added, waiting for FIRST_POLL_PACING of pacing at most.

        Where the vendor's pacing makes one read of every point longer, the first points are
        read now and the others by the poll that starts as soon as the entities are added.
        A failure raises for Home Assistant's setup retry or reauth, as a first refresh does.
        """
        every = self._poll
        self._poll = every[: self.client.points_read_within(every, FIRST_POLL_PACING)]
        try:
            await self.async_config_entry_first_refresh()
        finally:
            self._partial = len(self._poll) < len(every)
            self._poll = every

    async def _read_poll(self) -> ReadResult:
        """Read the polled points due (the poll's one read); note what changed since the last."""
        now = self.hass.loop.time()
        if self._started is not None:
            self.cycle = now - self._started
        self._started, self._partial, self._again, self._changed = now, False, False, None
        # A scheduled poll keeps the grid (its lateness never adds up); another starts one,
        # staggered within its second as Home Assistant staggers coordinators.
        at = self._grid if self._grid is not None else int(now) + self._stagger
        self._base, self._grid = at, None
        read = self.data.values if self.data is not None else {}
        if self.last_update_success:
            points, classes = self._schedule.due(self._poll, at, read, self._asked)
        else:  # a recovery reads every point: any may have changed while the link was down
            points, classes = self._poll, set(self._schedule.intervals)
        points = self._edited_first(points)
        self._reading = True
        try:
            result = await self.client.read(points, on_results=self._show_returned)
        finally:
            self._reading = False
        self._schedule.done(at, classes)
        if self._asked:
            self._asked.difference_update(points)
        if self.data is not None:
            if points is not self._poll:
                result = self._carry_over(result)
            values, changes = compared(self.data.values, result.values)
            result = replace(result, values=values)
            if self.last_update_success:
                self._changed = changes
        return result

    def _edited_first(self, points: list[Point]) -> list[Point]:
        """Return the points with those edits added read first (after `_lead`); they are read.

        On a paced PLC their values then come with the poll's first requests.
        """
        if not self._edited:
            return points
        lead = [point for point in points if point in self._lead]
        edited = [point for point in points if point in self._edited and point not in self._lead]
        self._edited.difference_update(points)
        if not edited:
            return points
        first = {*lead, *edited}
        return [*lead, *edited, *(point for point in points if point not in first)]

    @callback
    def _show_returned(self, values: dict[Point, PointResult]) -> None:
        """Show the results one request of a running read returned, where they changed.

        The schedule is left as it is and the other points keep what they show.
        """
        data: ReadResult | None = self.data  # None until the first poll has ended
        if data is None:
            return
        changed = {p: result for p, result in values.items() if data.values.get(p) != result}
        if changed:
            self._show(changed)

    def _carry_over(self, result: ReadResult) -> ReadResult:
        """Keep the results of the points this poll did not read (not due, or added since)."""
        old = self.data.values
        extra = {p: old[p] for p in self._poll if p not in result.values and p in old}
        return replace(result, values=result.values | extra) if extra else result

    @callback
    def _schedule_refresh(self) -> None:
        """Schedule the next poll an interval after the last one started (at once if past).

        Home Assistant's own counts the interval from the end of a poll: a poll the vendor's
        pacing made long pushed every later one back by its length.
        """
        if self.update_interval is None or self._reading:
            return
        if self.config_entry.pref_disable_polling:
            return
        self._cancel_poll()
        now = self.hass.loop.time()
        interval = self.update_interval.total_seconds()
        if self._retry_after is not None:  # an UpdateFailed asked for a later retry
            due, self._retry_after = int(now) + self._stagger + self._retry_after, None
        elif self._base is None:
            due = int(now) + self._stagger + interval
        elif self._partial or self._again:
            due = now
        else:
            due = max(now, self._base + interval)
        self._due = due
        if self._again and not self._partial:
            # Edited points wait for this poll: it starts now, not at the loop's next turn (a
            # wait for the tasks running, a test's or a stop's, sees it).
            self._poll_due()
            return
        self._unsub_refresh = self._call_at(due, self._poll_due, "poll")

    @callback
    def _reschedule(self) -> None:
        """Schedule a waiting poll again: the tick changed (a first fast point came)."""
        if self._unsub_refresh is not None:
            self._schedule_refresh()

    @callback
    def _cancel_poll(self) -> None:
        """Cancel the scheduled poll, if one is."""
        if self._unsub_refresh is not None:
            self._unsub_refresh()
            self._unsub_refresh = None

    @callback
    def _call_at(
        self, due: float, target: Callable[[HassJob[..., None]], None], what: str
    ) -> CALLBACK_TYPE:
        """Call `target` at loop time `due`, unless Home Assistant stops first."""
        job = HassJob(
            target, f"{self.name} {what}", job_type=HassJobType.Callback, cancel_on_shutdown=True
        )
        return self.hass.loop.call_at(due, target, job).cancel

    @callback
    def _poll_due(self, _job: HassJob[..., None] | None = None) -> None:
        """Start the due poll as a background task of the entry (cancelled when HA stops)."""
        self._unsub_refresh, self._grid = None, self._due
        self.config_entry.async_create_background_task(
            self.hass, self._async_poll(), f"{self.name} poll"
        )

    async def _async_poll(self) -> None:
        """Poll as scheduled, unless Home Assistant is stopping."""
        if not self.hass.is_stopping:
            await self.async_refresh()

    @callback
    def _queue_edited(self) -> None:
        """Read the polled points not read yet once edits pause for EDIT_DELAY."""
        read = self.data.values if self.data is not None else {}
        self._edited.update(point for point in self._poll if point not in read)
        if not self._edited:
            return
        self._cancel_edit_read()
        due = self.hass.loop.time() + EDIT_DELAY
        self._unsub_edit = self._call_at(due, self._edit_due, "edited points")

    @callback
    def _edit_due(self, _job: HassJob[..., None]) -> None:
        """Have the edited points read: by the poll running or due, else in a read of theirs.

        A poll that started since the edit reads them already; one running from before is
        followed at once by one that reads them first; a poll due before their own read would
        end starts now and reads them first. A read of their own runs in the background
        (cancelled when Home Assistant stops).
        """
        self._unsub_edit = None
        self._edited.intersection_update(self._poll)
        if self.hass.is_stopping or not self._edited or self.data is None:
            return
        if self._reading:
            self._again = True
            return
        now = self.hass.loop.time()
        own_read = self.client.min_scan_interval(list(self._edited))
        due = self._due if self._unsub_refresh is not None else None
        if due is not None and due <= now + own_read:
            self._cancel_poll()
            self._due = now
            self._poll_due()
            return
        self.config_entry.async_create_background_task(
            self.hass, self._async_read_edited(), f"{self.name} edited points"
        )

    async def _async_read_edited(self) -> None:
        """Read the points edits added, in one read, and show their values."""
        polled = set(self._poll)
        points = [point for point in self._edited if point in polled]
        self._edited.clear()
        if not points or self.data is None:
            return
        try:
            result = await self.client.read(points, poll=False, on_results=self._show_returned)
        except PlcError as err:
            LOGGER.debug("%s: edited points wait for the next poll: %s", self.name, err)
            return
        self._watch_points(result)
        self._show(result.values)

    def _watch_points(self, result: ReadResult) -> None:
        """Look at the outcome of the points edits added (the coordinator raises issues)."""

    @callback
    def _cancel_edit_read(self) -> None:
        """Forget a pending read of edited points."""
        if self._unsub_edit is not None:
            self._unsub_edit()
            self._unsub_edit = None

    async def async_shutdown(self) -> None:
        """Stop polling, and drop a pending read of edited points."""
        self._cancel_edit_read()
        await super().async_shutdown()

    @callback
    def _show(self, values: Mapping[Point, PointResult]) -> None:
        """Show these results at once, before the next poll reads every point."""
        self.data = replace(self.data, values=self.data.values | dict(values))
        self._changed = set(values)
        self.async_update_listeners()

    @callback
    def async_follow(self, entity: Follower, point: Point | None) -> None:
        """Update `entity` after polls that change `point` (None: after every poll)."""
        if not self._followers:
            self._unsub_followers = self.async_add_listener(self._followed)
        self._followers[entity] = point

    @callback
    def async_unfollow(self, entity: Follower) -> None:
        """Stop updating `entity`; polling stops with the last listener."""
        self._followers.pop(entity, None)
        if not self._followers and self._unsub_followers is not None:
            unsub = self._unsub_followers
            self._unsub_followers = None
            unsub()

    @callback
    def _followed(self) -> None:
        """The followers' one listener of the base: updates go through async_update_listeners."""

    @callback
    def async_update_listeners(self) -> None:
        """Update the entities of points whose result changed, and the PLC's own entities.

        Every entity is updated after a failed poll, a recovery and the first poll.
        """
        changes, self._changed = self._changed, None
        updates = [
            update
            for update, point in self._listeners.values()
            if update != self._followed and (changes is None or point is None or point in changes)
        ]
        for entity in [
            entity
            for entity, point in self._followers.items()
            if changes is None or point is None or point in changes
        ]:
            if entity.hass is None:  # Home Assistant aborted its add after it followed
                self.async_unfollow(entity)
            else:
                updates.append(entity._handle_coordinator_update)
        if len(updates) <= UPDATE_SLICE:
            self._update(updates)
            return
        self.config_entry.async_create_task(
            self.hass, self._async_update_in_slices(updates), f"{self.name} updates"
        )

    async def _async_update_in_slices(self, updates: list[CALLBACK_TYPE]) -> None:
        """Update the entities UPDATE_SLICE at a time, letting the loop run in between."""
        for start in range(0, len(updates), UPDATE_SLICE):
            if start:
                await asyncio.sleep(0)
            self._update(updates[start : start + UPDATE_SLICE])

    @callback
    def _update(self, updates: list[CALLBACK_TYPE]) -> None:
        """Call these entities' updates (each writes its state if what it shows changed)."""
        for update in updates:
            try:
                update()
            except Exception:
                LOGGER.exception("Unexpected error updating an entity of %s", self.name)


class PollSchedule:
    """Which points each poll reads: every class at its own interval, on the fastest's ticks."""

    def __init__(self) -> None:
        """Start with every point normal."""
        self.classes: dict[Point, str] = {}
        self.intervals: dict[str, float] = {}  # of the classes that have points
        self._normal = 0.0
        self._read: dict[str, float] = {}  # when each class was last read (a poll's time)

    def configure(self, classes: Mapping[Point, str], intervals: Mapping[str, float]) -> None:
        """Take each point's class (points left out: read at every poll) and the intervals."""
        self.classes = dict(classes)
        used = set(self.classes.values())
        self.intervals = {name: intervals[name] for name in POLL_CLASSES if name in used}
        self._normal = intervals[NORMAL]
        self._read = {name: at for name, at in self._read.items() if name in self.intervals}

    @property
    def tick(self) -> float:
        """Seconds between polls: the interval of the fastest class with points."""
        return min(self.intervals.values(), default=self._normal)

    def due(
        self, points: list[Point], at: float, read: Container[Point], wanted: Collection[Point]
    ) -> tuple[list[Point], set[str]]:
        """Return the points a poll at `at` reads, and the classes it reads.

        `read`: the points read before (others are read at once); `wanted`: points a write
        asks back. Where every class is due, or there is only one, `points` itself is returned.
        """
        if len(self.intervals) <= 1:
            return points, set(self.intervals)
        half = self.tick / 2
        due = {
            name
            for name, interval in self.intervals.items()
            if at - self._read.get(name, -math.inf) >= interval - half
        }
        if len(due) == len(self.intervals):
            return points, due
        return [
            point
            for point in points
            if (name := self.classes.get(point)) is None
            or name in due
            or point not in read
            or point in wanted
        ], due

    def done(self, at: float, classes: Iterable[str]) -> None:
        """Note that a poll at `at` read these classes."""
        for name in classes:
            self._read[name] = at

    def counts(self) -> dict[str, int]:
        """Return how many points each class has."""
        counts = dict.fromkeys(self.intervals, 0)
        for name in self.classes.values():
            counts[name] += 1
        return counts
