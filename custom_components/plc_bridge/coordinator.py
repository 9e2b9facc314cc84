"""One coordinator per PLC: the points due in one planned read per poll, errors mapped once."""

from __future__ import annotations

from collections import deque
from collections.abc import Collection, Iterable, Mapping
from datetime import datetime, timedelta
from typing import TYPE_CHECKING

from homeassistant.core import HomeAssistant, callback
from homeassistant.exceptions import (
    ConfigEntryAuthFailed,
    ConfigEntryNotReady,
    HomeAssistantError,
)
from homeassistant.helpers.update_coordinator import UpdateFailed

from .const import CONF_TLS, DOMAIN, LOGGER
from .model.composite import point_classes
from .model.poll_classes import class_intervals
from .plc import (
    PlcAddressError,
    PlcAuthenticationError,
    PlcClient,
    PlcConnectionError,
    PlcError,
    PlcTlsError,
    Point,
    PointResult,
    ReadResult,
    TlsMode,
    Value,
)
from .runtime.availability import MachineAvailability
from .runtime.errors import check_can_write, named, translated_errors
from .runtime.issues import (
    CERTIFICATE_CHANGED,
    SESSION_CONFLICT,
    async_clear_issue,
    async_clear_point_issue,
    async_clear_point_issues,
    async_point_issues,
    async_raise_issue,
    async_raise_point_issue,
)
from .runtime.polling import PollingCoordinator
from .runtime.restore import StoredValues
from .runtime.write_guard import WriteGuard

if TYPE_CHECKING:
    from .model.points import PointConfig
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from homeassistant.config_entries import ConfigEntry

from .plc import DeviceInfo
from .runtime.entities import PointEntities

__all__ = ["PlcBridgeConfigEntry", "PlcCoordinator", "PlcRuntimeData", "link_error"]

RENEWAL_WINDOW = 10
"""Polls over which session renewals are counted."""
RENEWAL_LIMIT = 3
"""Renewals within the window that mean another client logs in with the same PLC user."""


def link_error(
    hass: HomeAssistant, entry: PlcBridgeConfigEntry, err: PlcError, *, setup: bool
) -> HomeAssistantError:
    """Return the error for a failed connect (setup) or poll; a changed pin raises an issue.

    In pin mode the certificate is compared during the TLS handshake, before any request is
    written, so retrying never hands the credentials to the device that answered instead.
    """
    if isinstance(err, PlcAuthenticationError):
        return ConfigEntryAuthFailed(
            translation_domain=DOMAIN,
            translation_key="invalid_auth",
            translation_placeholders={"error": str(err)},
        )
    key = "communication_error"
    if isinstance(err, PlcTlsError):
        key = "tls_failed"
        if entry.data.get(CONF_TLS) == TlsMode.PIN:
            async_raise_issue(hass, entry, CERTIFICATE_CHANGED)
    elif isinstance(err, PlcConnectionError):
        key = "cannot_connect"
    error = ConfigEntryNotReady if setup else UpdateFailed
    return error(
        translation_domain=DOMAIN,
        translation_key=key,
        translation_placeholders={"error": str(err)},
    )


class PlcCoordinator(PollingCoordinator):
    """Poll every point of one PLC in one planned read, and write through the same client."""

    def __init__(
        self,
        hass: HomeAssistant,
        entry: PlcBridgeConfigEntry,
        client: PlcClient,
        points: Mapping[str, PointConfig],
    ) -> None:
        """Collect the points and choose the poll interval the vendor's request rate allows."""
        super().__init__(hass, entry, client)
        self.availability = MachineAvailability(entry.title)
        self.stored = StoredValues(hass, entry)
        """The points' values kept across restarts (runtime/restore.py)."""
        self.stored.follow(self._kept)
        self._set_points(points)
        self._failing: set[Point] = set()
        # The others stay open until their point reads, even those a previous setup raised.
        self._unknown = async_point_issues(hass, entry)
        self._renewals: deque[int] = deque(maxlen=RENEWAL_WINDOW)
        self._renewals_seen = client.metrics.session_renewals

    def _set_points(self, points: Mapping[str, PointConfig]) -> None:
        """Poll these points (by point id) from now on, at an interval the vendor allows."""
        self.points = {point_id: config.point for point_id, config in points.items()}
        self.names = {point_id: config.name for point_id, config in points.items()}
        self.read_only_points = frozenset(
            config.point for config in points.values() if config.read_only
        )
        self.write_guard = WriteGuard(self.client, self.read_only_points)
        self.availability.configure(self.config_entry.subentries.values())
        self._machines: dict[str, set[Point]] = {}
        for config in points.values():
            self._machines.setdefault(config.subentry_id, set()).add(config.point)
        # Availability points first: a paced first poll reads them with the first points.
        self._lead = frozenset(self.availability.points.values())
        self._poll = list(
            dict.fromkeys([*self.availability.points.values(), *self.points.values()])
        )
        classes = point_classes(points, self.availability.points.values())
        options = self.config_entry.options
        self._schedule.configure(
            classes, class_intervals(type(self.client), options, classes, self._poll)
        )
        self.update_interval = timedelta(seconds=self._schedule.tick)
        # A removed point's issue goes with it.
        async_clear_point_issues(self.hass, self.config_entry, keep=self.points)

    def _kept(self) -> tuple[Mapping[Point, PointResult], Collection[Point]]:
        """The last poll's results, and the points whose values are kept across restarts."""
        return (self.data.values if self.data is not None else {}), self.points.values()

    @callback
    def async_set_points(self, points: Mapping[str, PointConfig]) -> None:
        """Follow edited points; the new ones are read together once the edits pause."""
        invalid, tick = set(self.availability.invalid), self.update_interval
        self._set_points(points)
        if self.update_interval != tick:
            self._reschedule()  # a first fast point: the next poll comes sooner
        if invalid - self.availability.invalid:  # a machine no longer names its address
            self._changed = None
            self.async_update_listeners()
        self._unknown &= set(self.points)
        self._queue_edited()

    async def _async_update_data(self) -> ReadResult:
        """Read every point at once; a point's own failure stays in its result."""
        try:
            result = await self._read_poll()
        except PlcError as err:
            raise link_error(self.hass, self.config_entry, err, setup=False) from err
        finally:
            self._watch_sessions()
        if self.config_entry.data.get(CONF_TLS) == TlsMode.PIN:
            async_clear_issue(self.hass, self.config_entry, CERTIFICATE_CHANGED)
        self._log_point_changes(result)
        self._watch_addresses(result, self._failing)
        if self.availability.watch(result.values):
            self._changed = None  # a machine's entities changed availability: update them all
        for machine in self.availability.invalid:
            # Read whatever their class, so the poll that finds its data valid again reads them.
            self._asked.update(self._machines.get(machine, set()) & result.values.keys())
        self.stored.polled(result.values.keys())
        return result

    def _watch_points(self, result: ReadResult) -> None:
        """Raise or clear the issues of the points edits added, as a poll would."""
        failing = {point for point, outcome in result.values.items() if not outcome.ok}
        self._watch_addresses(result, failing)

    def _log_point_changes(self, result: ReadResult) -> None:
        """Log a point when it starts failing and when it recovers, not at every poll."""
        failing = {point for point, outcome in result.values.items() if not outcome.ok}
        for point in failing - self._failing:
            LOGGER.warning(
                "%s: cannot read %s (%s): %s",
                self.name,
                point.address,
                point.data_type,
                result.values[point].error,
            )
        for point in self._failing - failing:
            LOGGER.info("%s: %s (%s) can be read again", self.name, point.address, point.data_type)
        self._failing = failing

    def _watch_addresses(self, result: ReadResult, failing: set[Point]) -> None:
        """Raise one issue per point whose address the PLC does not know; clear it once it reads.

        Vendor-neutral: any PlcAddressError counts, whether the point read fine before (a
        renamed PLC variable) or fails at every poll; the other points are read regardless.
        """
        if not failing and not self._unknown:
            return  # every point read and no issue is open: nothing to look at
        for point_id, point in self.points.items():
            outcome = result.values.get(point)
            if outcome is None:
                continue
            if isinstance(outcome.error, PlcAddressError):
                if point_id not in self._unknown:
                    self._unknown.add(point_id)
                    async_raise_point_issue(
                        self.hass,
                        self.config_entry,
                        point_id,
                        name=self.names[point_id],
                        address=point.address,
                        error=str(outcome.error),
                    )
            elif outcome.ok and point_id in self._unknown:
                self._unknown.discard(point_id)
                async_clear_point_issue(self.hass, self.config_entry, point_id)

    def _watch_sessions(self) -> None:
        """Raise an issue while the PLC keeps dropping the session (its user logs in elsewhere)."""
        renewals = self.client.metrics.session_renewals
        self._renewals.append(renewals - self._renewals_seen)
        self._renewals_seen = renewals
        recent = sum(self._renewals)
        if recent >= RENEWAL_LIMIT:
            async_raise_issue(self.hass, self.config_entry, SESSION_CONFLICT)
        elif recent == 0:
            async_clear_issue(self.hass, self.config_entry, SESSION_CONFLICT)

    async def async_set_clock(self, when: datetime) -> None:
        """Set the PLC clock, then poll so that clock points and the clock entity show it."""
        check_can_write(self.config_entry)
        with translated_errors(self.hass, self.config_entry):
            await self.client.set_clock(when)
        self.ask_back(self._poll)  # whatever their class: clock points may be slow
        await self.async_request_refresh()

    async def async_write_values(self, values: Mapping[Point, Value]) -> dict[Point, PointResult]:
        """Write the values in one call after the checks every write passes; show what was taken.

        Raises before anything is sent (no permission, a read-only point) and for a link error;
        a point the PLC refused keeps its error in its result. Exposes write through this alone.
        """
        check_can_write(self.config_entry)
        for point in values:
            self.write_guard.check(point)
        with translated_errors(self.hass, self.config_entry):
            results = await self.client.write(values)
        taken = {
            point: PointResult(value=result.value)
            for point, result in results.items()
            if result.ok and result.value is not None and point in self.data.values
        }
        if taken:
            self._show(taken)
        return results

    async def async_write(
        self, values: Mapping[Point, Value], *, read_back: Iterable[Point] = ()
    ) -> None:
        """Write the values in one call, then refresh; any point the PLC refused is an error.

        The points the PLC took show their new value at once; the refresh that follows (held
        back by the debouncer after a burst of writes) reads back what the PLC really holds:
        the written points and `read_back` (an entity's other parts), whatever their class.
        """
        results = await self.async_write_values(values)
        self.ask_back([*values, *read_back])
        await self.async_request_refresh()
        failed = [named(point, res.error) for point, res in results.items() if res.error]
        if failed:
            raise HomeAssistantError(
                translation_domain=DOMAIN,
                translation_key="write_failed",
                translation_placeholders={"error": "; ".join(failed)},
            )


@dataclass(slots=True, kw_only=True)
class PlcRuntimeData:
    """What a loaded entry keeps: the connected client, its coordinator, what the PLC said."""

    client: PlcClient
    coordinator: PlcCoordinator
    device: DeviceInfo
    points: PointEntities
    settings: tuple[dict[str, Any], dict[str, Any]]
    """The entry's data and options at setup: a change of these reloads the entry."""


type PlcBridgeConfigEntry = ConfigEntry[PlcRuntimeData]
