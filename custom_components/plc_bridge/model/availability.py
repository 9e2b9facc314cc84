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
    TextSelector,
)
import voluptuous as vol

from ..const import SUBENTRY_DEVICE
from ..plc import PlcClient, PlcError, Point, Value
from .points import data_type_selector

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
        vol.Optional(CONF_AVAILABILITY_DATA_TYPE, default=types[0]): data_type_selector(client),
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


def availability_points(subentries: Iterable[Any]) -> dict[str, Point]:
    """Return the availability point of every machine (device subentry) that names one."""
    return {
        subentry.subentry_id: Point(
            subentry.data[CONF_AVAILABILITY_ADDRESS],
            subentry.data.get(CONF_AVAILABILITY_DATA_TYPE, ""),
        )
        for subentry in subentries
        if subentry.subentry_type == SUBENTRY_DEVICE
        and subentry.data.get(CONF_AVAILABILITY_ADDRESS)
    }
