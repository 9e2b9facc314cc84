"""Diagnostic entities of the link to a PLC: can it be reached, and what its polls cost."""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from datetime import datetime
from typing import Any

from homeassistant.components.binary_sensor import (  # type: ignore[attr-defined]
    BinarySensorDeviceClass,
    BinarySensorEntity,
    BinarySensorEntityDescription,
)
from homeassistant.components.sensor import (
    SensorDeviceClass,
    SensorEntity,
    SensorEntityDescription,
    SensorStateClass,
)
from homeassistant.const import EntityCategory, UnitOfTime
from homeassistant.util import dt as dt_util

from .coordinator import PlcBridgeConfigEntry, PlcCoordinator
from .entity import PlcEntity

POLL_STEP = 0.1
"""Seconds the poll duration must move before it is shown anew (or POLL_SHARE of it, if more)."""
POLL_SHARE = 0.1
"""Share of the shown poll duration it must move by before it is shown anew."""
REQUEST_WINDOW = 300.0
"""Seconds a poll's request count is shown for at least: longer than any vendor's status pace."""

CONNECTIVITY = BinarySensorEntityDescription(
    key="connectivity",
    device_class=BinarySensorDeviceClass.CONNECTIVITY,
    entity_category=EntityCategory.DIAGNOSTIC,
)
POLL_DURATION = SensorEntityDescription(
    key="poll_duration",
    translation_key="poll_duration",
    device_class=SensorDeviceClass.DURATION,
    native_unit_of_measurement=UnitOfTime.SECONDS,
    suggested_display_precision=2,
    state_class=SensorStateClass.MEASUREMENT,
    entity_category=EntityCategory.DIAGNOSTIC,
    entity_registry_enabled_default=False,
)
LAST_POLL = SensorEntityDescription(
    key="last_poll",
    translation_key="last_poll",
    device_class=SensorDeviceClass.TIMESTAMP,
    entity_category=EntityCategory.DIAGNOSTIC,
    # Its state changes at every successful poll by nature: off unless asked for.
    entity_registry_enabled_default=False,
)


@dataclass(frozen=True, kw_only=True)
class PlcLinkCountDescription(SensorEntityDescription):
    """A count the last poll gives, shown as a diagnostic sensor."""

    value_fn: Callable[[PlcCoordinator], int]


POLL_REQUESTS = SensorEntityDescription(
    key="poll_requests",
    translation_key="poll_requests",
    state_class=SensorStateClass.MEASUREMENT,
    entity_category=EntityCategory.DIAGNOSTIC,
    entity_registry_enabled_default=False,
)
POINTS_FAILING = PlcLinkCountDescription(
    key="points_failing",
    translation_key="points_failing",
    state_class=SensorStateClass.MEASUREMENT,
    entity_category=EntityCategory.DIAGNOSTIC,
    entity_registry_enabled_default=False,
    value_fn=lambda coordinator: sum(not result.ok for result in coordinator.data.values.values()),
)


def link_sensors(entry: PlcBridgeConfigEntry) -> list[SensorEntity]:
    """Return the sensors of what the polls of the entry's PLC cost."""
    return [
        PlcPollDuration(entry),
        PlcPollRequests(entry),
        PlcLinkCount(entry, POINTS_FAILING),
        PlcLastPoll(entry),
    ]


class PlcConnectivity(PlcEntity, BinarySensorEntity):
    """On while polls reach the PLC, off (not unavailable) while they cannot."""

    entity_description = CONNECTIVITY

    def __init__(self, entry: PlcBridgeConfigEntry) -> None:
        """Bind the sensor to the PLC's polls."""
        super().__init__(entry, CONNECTIVITY.key)

    @property
    def available(self) -> bool:
        """Always available: an unreachable PLC is what this sensor shows."""
        return True

    @property
    def is_on(self) -> bool:
        """Return whether the last poll reached the PLC."""
        return self.coordinator.last_update_success

    def observed(self) -> Any:
        """Whether the last poll reached the PLC."""
        return self.is_on


class PlcLinkCount(PlcEntity, SensorEntity):
    """A count of the last poll."""

    entity_description: PlcLinkCountDescription

    def __init__(self, entry: PlcBridgeConfigEntry, description: PlcLinkCountDescription) -> None:
        """Bind the sensor to its count."""
        super().__init__(entry, description.key)
        self.entity_description = description

    @property
    def native_value(self) -> int:
        """Return the count of the last poll."""
        return self.entity_description.value_fn(self.coordinator)

    def observed(self) -> Any:
        """The count of the last poll."""
        return self.native_value


class RecentPeak:
    """The largest value successful polls gave within the last REQUEST_WINDOW seconds.

    Polls differ by design: a status read at the vendor's own pace (the S7: once a minute),
    or poll classes (a poll of every class takes longer than one of the fast points): the
    peak stays shown, so a state is written when the polls change, not at every such switch.
    """

    def __init__(self, coordinator: PlcCoordinator) -> None:
        """Follow the coordinator's client's polls."""
        self._coordinator = coordinator
        self._polls = -1
        self._seen: deque[tuple[float, float]] = deque()  # (loop time, value), values falling

    def take(self, value: float) -> float | None:
        """Take the value of a successful poll newer than the last; return the peak (None: none)."""
        metrics = self._coordinator.client.metrics
        if metrics.polls != self._polls and self._coordinator.last_update_success:
            self._polls = metrics.polls
            now = self._coordinator.hass.loop.time()
            while self._seen and self._seen[-1][1] <= value:
                self._seen.pop()
            self._seen.append((now, value))
            while self._seen[0][0] < now - REQUEST_WINDOW:
                self._seen.popleft()
        return self._seen[0][1] if self._seen else None


class PlcPollRequests(PlcEntity, SensorEntity):
    """The most requests a successful poll took within the last REQUEST_WINDOW (RecentPeak)."""

    entity_description = POLL_REQUESTS

    def __init__(self, entry: PlcBridgeConfigEntry) -> None:
        """Bind the sensor to the client's poll metrics (the setup's poll just succeeded)."""
        super().__init__(entry, POLL_REQUESTS.key)
        self._recent = RecentPeak(self.coordinator)
        self._peak = 0
        self._measure()

    def _measure(self) -> None:
        """Take the request count of a successful poll newer than the last one seen."""
        requests = self.coordinator.client.metrics.last_poll_requests
        self._peak = int(self._recent.take(requests) or 0)

    @property
    def native_value(self) -> int:
        """Return the most requests a recent poll took."""
        return self._peak

    def observed(self) -> Any:
        """The count shown, updated from the last poll."""
        self._measure()
        return self._peak


class PlcPollDuration(PlcEntity, SensorEntity):
    """The longest a successful poll took within the last REQUEST_WINDOW (RecentPeak), in s.

    Shown anew only when it moves by POLL_STEP or POLL_SHARE of itself, whichever is more:
    a duration varies by milliseconds from poll to poll (the network, the PLC's own cycle),
    and a threshold rather than rounding keeps a duration near a rounding edge from flapping.
    """

    entity_description = POLL_DURATION

    def __init__(self, entry: PlcBridgeConfigEntry) -> None:
        """Bind the sensor to the client's poll metrics."""
        super().__init__(entry, POLL_DURATION.key)
        self._recent = RecentPeak(self.coordinator)
        self._duration: float | None = None
        self._measure()

    def _measure(self) -> None:
        """Take the longest recent poll's duration if it moved past the threshold."""
        duration = self._recent.take(self.coordinator.client.metrics.last_poll_ms / 1000)
        shown = self._duration
        if duration is None:
            return
        if shown is None or abs(duration - shown) >= max(POLL_STEP, POLL_SHARE * shown):
            self._duration = round(duration, 2)

    @property
    def native_value(self) -> float | None:
        """Return the duration shown."""
        return self._duration

    def observed(self) -> Any:
        """The duration shown, updated from the last poll."""
        self._measure()
        return self._duration


class PlcLastPoll(PlcEntity, SensorEntity):
    """When a poll last reached the PLC; stays available while polls fail, to say since when."""

    entity_description = LAST_POLL

    def __init__(self, entry: PlcBridgeConfigEntry) -> None:
        """Bind the sensor to the PLC's polls (the setup's poll just succeeded)."""
        super().__init__(entry, LAST_POLL.key)
        self._polls = self.coordinator.client.metrics.polls
        self._last = dt_util.utcnow()

    def _measure(self) -> None:
        """Note the time of a successful poll newer than the last one seen."""
        polls = self.coordinator.client.metrics.polls
        if polls != self._polls:
            self._polls = polls
            if self.coordinator.last_update_success:
                self._last = dt_util.utcnow()

    @property
    def available(self) -> bool:
        """Always available (a poll succeeded at setup): it tells since when polls fail."""
        return True

    @property
    def native_value(self) -> datetime:
        """Return the time of the last successful poll."""
        return self._last

    def observed(self) -> Any:
        """The time of the last successful poll."""
        self._measure()
        return self._last
