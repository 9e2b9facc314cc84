"""Availability per machine: an address whose value says whether the machine's data is valid.

A machine (device subentry) may name one point, read at every poll (and, while it says not
valid, the machine's points with it, whatever their poll class: coordinator.py). Its data is
valid while that point reads true or non-zero, or, where a list of values is given, one of
them. While it reads "not valid" or fails, every entity of the machine is unavailable; the log
says so once on each change.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any, Final

from homeassistant.helpers.selector import (
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
    TextSelector,
)
import voluptuous as vol

from .const import CONF_DATA_TYPE, LOGGER, SUBENTRY_DEVICE
from .plc import PlcClient, PlcError, Point, PointResult, Value

CONF_AVAILABILITY_ADDRESS: Final = "availability_address"
CONF_AVAILABILITY_DATA_TYPE: Final = "availability_data_type"
CONF_AVAILABILITY_VALUES: Final = "availability_values"
AVAILABILITY_FIELDS: Final = (
    CONF_AVAILABILITY_ADDRESS,
    CONF_AVAILABILITY_DATA_TYPE,
    CONF_AVAILABILITY_VALUES,
)


class AvailabilityValuesError(ValueError):
    """The list of valid values holds something that is not a number."""


def parse_values(text: str) -> list[float]:
    """Return the numbers of a list such as `1; 3` (commas or semicolons between them)."""
    values: list[float] = []
    for item in text.replace(",", ";").split(";"):
        if item := item.strip():
            try:
                values.append(float(item))
            except ValueError as err:
                raise AvailabilityValuesError(item) from err
    return values


def is_valid(value: Value | None, values: Iterable[float]) -> bool:
    """Return whether a read value says the data is valid (true/non-zero, or one of values)."""
    wanted = list(values)
    if isinstance(value, bool | int | float):
        return float(value) in wanted if wanted else bool(value)
    return False if wanted else bool(value)


def availability_fields(client: type[PlcClient]) -> dict[vol.Optional, Any]:
    """Return the machine form's availability fields (address, data type, valid values)."""
    types = list(client.data_types)
    return {
        vol.Optional(CONF_AVAILABILITY_ADDRESS): TextSelector(),
        vol.Optional(CONF_AVAILABILITY_DATA_TYPE, default=types[0]): SelectSelector(
            SelectSelectorConfig(
                options=types,
                translation_key=CONF_DATA_TYPE,
                mode=SelectSelectorMode.DROPDOWN,
                custom_value=True,  # the vendor's parser checks it
            )
        ),
        vol.Optional(CONF_AVAILABILITY_VALUES): TextSelector(),
    }


def shown_availability(stored: Mapping[str, Any]) -> dict[str, Any]:
    """Return the stored availability fields as the form shows them."""
    shown = {key: stored[key] for key in AVAILABILITY_FIELDS if key in stored}
    if values := shown.get(CONF_AVAILABILITY_VALUES):
        shown[CONF_AVAILABILITY_VALUES] = "; ".join(f"{value:g}" for value in values)
    return shown


def check_availability(
    client: type[PlcClient], user_input: Mapping[str, Any]
) -> tuple[dict[str, Any], dict[str, str], str]:
    """Check the form's availability fields; return what to store, the errors and their detail."""
    address = str(user_input.get(CONF_AVAILABILITY_ADDRESS, "")).strip()
    if not address:
        return {}, {}, ""
    data_type = str(user_input.get(CONF_AVAILABILITY_DATA_TYPE, "")).strip()
    try:
        point = client.validate_point(Point(address, data_type))
    except PlcError as err:
        return {}, {CONF_AVAILABILITY_ADDRESS: "invalid_address"}, str(err)
    try:
        values = parse_values(str(user_input.get(CONF_AVAILABILITY_VALUES, "")))
    except AvailabilityValuesError as err:
        return {}, {CONF_AVAILABILITY_VALUES: "invalid_availability_values"}, str(err)
    stored: dict[str, Any] = {
        CONF_AVAILABILITY_ADDRESS: point.address,
        CONF_AVAILABILITY_DATA_TYPE: point.data_type,
    }
    if values:
        stored[CONF_AVAILABILITY_VALUES] = values
    return stored, {}, ""


class MachineAvailability:
    """Which machines' data is valid, from their availability points in each poll."""

    def __init__(self, name: str) -> None:
        """Start with no availability points: every machine is valid."""
        self._name = name
        self.points: dict[str, Point] = {}
        self._values: dict[str, list[float]] = {}
        self._titles: dict[str, str] = {}
        self.invalid: set[str] = set()

    def configure(self, subentries: Iterable[Any]) -> None:
        """Take the availability point of every machine that names one."""
        self.points, self._values, self._titles = {}, {}, {}
        for subentry in subentries:
            data: Mapping[str, Any] = subentry.data
            address = data.get(CONF_AVAILABILITY_ADDRESS)
            if subentry.subentry_type != SUBENTRY_DEVICE or not address:
                continue
            sid = subentry.subentry_id
            self.points[sid] = Point(address, data.get(CONF_AVAILABILITY_DATA_TYPE, ""))
            self._values[sid] = [float(v) for v in data.get(CONF_AVAILABILITY_VALUES, [])]
            self._titles[sid] = subentry.title
        self.invalid = self.invalid & set(self.points)

    def watch(self, values: Mapping[Point, PointResult]) -> bool:
        """Follow one poll's results; return True when a machine's availability changed."""
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
