"""A machine's data-valid point as the polls read it: its entities unavailable while not valid."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from datetime import datetime
from typing import Any

from homeassistant.util import dt as dt_util

from ..const import LOGGER
from ..model.availability import (
    CONF_AVAILABILITY_VALUES,
    availability_points,
    is_valid,
)
from ..plc import Point, PointResult


class MachineAvailability:
    """Which machines' data is valid, from their availability points in each poll."""

    def __init__(self, name: str) -> None:
        """Start with no availability points: every machine is valid."""
        self._name = name
        self.points: dict[str, Point] = {}
        self._values: dict[str, list[float]] = {}
        self._titles: dict[str, str] = {}
        self.invalid: set[str] = set()
        self.read_at: datetime | None = None
        """When the last poll that reached the PLC ended: what values kept were read by."""

    def configure(self, subentries: Iterable[Any]) -> None:
        """Take the availability point of every machine that names one."""
        subentries = list(subentries)
        self.points = availability_points(subentries)
        stored = {subentry.subentry_id: subentry for subentry in subentries}
        self._values = {
            sid: [float(v) for v in stored[sid].data.get(CONF_AVAILABILITY_VALUES, [])]
            for sid in self.points
        }
        self._titles = {sid: stored[sid].title for sid in self.points}
        self.invalid = self.invalid & set(self.points)

    def watch(self, values: Mapping[Point, PointResult]) -> bool:
        """Follow one poll's results; return True when a machine's availability changed."""
        self.read_at = dt_util.utcnow()
        invalid, reasons = set(self.invalid), dict[str, str]()
        for sid, point in self.points.items():
            result = values.get(point)
            if result is None:
                continue  # not read by this (partial) poll: unchanged
            if result.ok and is_valid(result.value, self._values[sid]):
                invalid.discard(sid)
                continue
            invalid.add(sid)
            reasons[sid] = "says its data is not valid" if result.ok else "cannot be read"
        for sid in invalid - self.invalid:
            LOGGER.warning(
                "%s: %s is unavailable: %s %s",
                self._name,
                self._titles[sid],
                self.points[sid].address,
                reasons[sid],
            )
        for sid in self.invalid - invalid:
            LOGGER.info("%s: %s is available again", self._name, self._titles[sid])
        changed = invalid != self.invalid
        self.invalid = invalid
        return changed
