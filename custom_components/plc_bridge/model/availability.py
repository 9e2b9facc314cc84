"""Availability per machine: an address whose value says whether the machine's data is valid.

A machine (device subentry) may name one point, read at every poll (and, while it says not
valid, the machine's points with it, whatever their poll class: coordinator.py). Its data is
valid while that point reads true or non-zero, or, where a list of values is given, one of
them. While it reads "not valid" or fails, every entity of the machine is unavailable; the log
says so once on each change.

Each entity has an availability policy, stored on its point (on every part of an entity of
several points): follow the PLC (unavailable while its value cannot be read), keep the last
value while the PLC cannot be reached, or follow the machine's data-valid address as well (only
where the machine names one, and its default there). No key: the machine's default.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any, Final

from homeassistant.const import CONF_NAME
from homeassistant.helpers.selector import (
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
    TextSelector,
)
import voluptuous as vol

from ..const import CONF_PLATFORM, CONF_ROLE, SUBENTRY_DEVICE
from ..plc import PlcClient, PlcError, Point, Value
from .composite import is_part
from .points import data_type_selector

CONF_AVAILABILITY_ADDRESS: Final = "availability_address"
CONF_AVAILABILITY_DATA_TYPE: Final = "availability_data_type"
CONF_AVAILABILITY_VALUES: Final = "availability_values"
CONF_AVAILABILITY_POLICY: Final = "availability"
POLICY_PLC: Final = "plc"
POLICY_KEEP: Final = "keep"
POLICY_DATA_VALID: Final = "data_valid"
POLICIES: Final = (POLICY_PLC, POLICY_KEEP, POLICY_DATA_VALID)
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


def has_data_valid(machine: Mapping[str, Any]) -> bool:
    """Return whether a machine's stored data names a data-valid address."""
    return bool(machine.get(CONF_AVAILABILITY_ADDRESS))


def default_policy(*, data_valid: bool) -> str:
    """Return the policy of a point that stores none: today's behaviour of its machine."""
    return POLICY_DATA_VALID if data_valid else POLICY_PLC


def policy_of(policy: str | None, *, data_valid: bool) -> str:
    """Return the policy of a point storing `policy`; `data_valid` without the address: `plc`."""
    if policy not in POLICIES or (policy == POLICY_DATA_VALID and not data_valid):
        return default_policy(data_valid=data_valid)
    return str(policy)


def policy_field(*, data_valid: bool) -> dict[vol.Optional, Any]:
    """Return the forms' availability policy field (`data_valid` only where the machine has it)."""
    options = [p for p in POLICIES if data_valid or p != POLICY_DATA_VALID]
    return {
        vol.Optional(
            CONF_AVAILABILITY_POLICY, default=default_policy(data_valid=data_valid)
        ): SelectSelector(
            SelectSelectorConfig(
                options=options,
                translation_key=CONF_AVAILABILITY_POLICY,
                mode=SelectSelectorMode.DROPDOWN,
            )
        )
    }


def check_policy(values: Mapping[str, Any], *, data_valid: bool) -> tuple[dict[str, str], str]:
    """Return what a point stores of its policy (nothing for the default), or the error key.

    The one check of the forms, the tables and the pasted file.
    """
    policy = str(values.get(CONF_AVAILABILITY_POLICY) or "").strip()
    if not policy:
        return {}, ""
    if policy not in POLICIES:
        return {}, "invalid_availability_policy"
    if policy == POLICY_DATA_VALID and not data_valid:
        return {}, "availability_policy_no_address"
    if policy == default_policy(data_valid=data_valid):
        return {}, ""
    return {CONF_AVAILABILITY_POLICY: policy}, ""


def policy_differs(rows: Iterable[Mapping[str, Any]]) -> list[str]:
    """Return the names of entities of several points whose parts store different policies."""
    policies: dict[tuple[str, str], set[str]] = {}
    for data in rows:
        platform = str(data.get(CONF_PLATFORM, ""))
        if is_part(platform, data.get(CONF_ROLE)):
            key = (platform, str(data.get(CONF_NAME, "")))
            policies.setdefault(key, set()).add(str(data.get(CONF_AVAILABILITY_POLICY, "")))
    return [name for (_, name), found in policies.items() if len(found) > 1]
