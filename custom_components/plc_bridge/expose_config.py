"""What one expose is: its stored settings, the PLC value a state becomes, its running state.

An expose subentry stores the entity (and optionally one of its attributes), the PLC address
and data type, and how the state is converted: a value map (`on=1;off=0`, `home=1;not_home=0`)
names the PLC value of a state; any other state is taken as a number, written as
number × scale + offset. Without a map, `on`/`off` and `true`/`false` mean 1 and 0.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
import math
from typing import Any

from homeassistant.const import CONF_ATTRIBUTE, CONF_ENTITY_ID, STATE_UNAVAILABLE, STATE_UNKNOWN
from homeassistant.core import CALLBACK_TYPE, Event, HomeAssistant, State, callback
from homeassistant.helpers import entity_registry as er

from .const import (
    CONF_ADDRESS,
    CONF_COOLDOWN,
    CONF_DATA_TYPE,
    CONF_DEFAULT,
    CONF_OFFSET,
    CONF_RESEND,
    CONF_SCALE,
    CONF_SEND_ON_START,
    CONF_VALUE_MAP,
    SUBENTRY_EXPOSE,
)
from .conversion import InvalidPairs, pair_parts, scaled
from .models import PlcBridgeConfigEntry
from .plc import PlcClient, PlcValueError, Point, Value, ValueKind

type StateMap = tuple[tuple[str, int | float], ...]
"""States (as typed) and the PLC value each is written as."""
UNSET = frozenset({STATE_UNAVAILABLE, STATE_UNKNOWN})
SWITCHED = {"on": 1, "off": 0, "true": 1, "false": 0}
"""What the states of a switch or binary sensor write where no value map is given."""
DEFAULT_COOLDOWN = 1.0
"""Seconds between two writes of one expose unless the user sets otherwise."""
SENDABLE = frozenset({ValueKind.BOOL, ValueKind.INTEGER, ValueKind.FLOAT, ValueKind.TEXT})
"""Kinds of PLC value an expose can write (not times, durations or raw bytes)."""


def _number(text: str) -> int | float | None:
    """Return the number a text spells (`1`, `0x10`, `2.5`), None for any other text."""
    text = text.strip()
    try:
        return int(text, 0)
    except ValueError:
        pass
    try:
        number = float(text)
    except ValueError:
        return None
    return number if math.isfinite(number) else None


def parse_state_map(text: str) -> StateMap:
    """Return `on=1;off=0` as pairs (`1=on` is taken too); raise InvalidPairs where it fails."""
    pairs: list[tuple[str, int | float]] = []
    for part, left, right in pair_parts(text):
        state, number = left, _number(right)
        if number is None and _number(left) is not None:
            state, number = right, _number(left)
        if not state or number is None:
            raise InvalidPairs("map_not_a_pair", part)
        if any(state.casefold() == known.casefold() for known, _ in pairs):
            raise InvalidPairs("map_repeated", part)
        pairs.append((state, number))
    return tuple(pairs)


def format_state_map(pairs: StateMap) -> str:
    """Return pairs in their stored form, `on=1;off=0`."""
    return ";".join(f"{state}={value}" for state, value in pairs)


@dataclass(frozen=True, slots=True, kw_only=True)
class ExposeConfig:
    """One expose as its subentry stores it."""

    subentry_id: str
    title: str
    entity_id: str
    attribute: str | None
    point: Point
    scale: float = 1.0
    offset: float = 0.0
    value_map: StateMap = ()
    cooldown: float = DEFAULT_COOLDOWN
    resend: float = 0.0
    send_on_start: bool = True
    default: str | None = None

    def source(self, state: State | None) -> Any:
        """Return the state or attribute to send; the default (or None) while there is none."""
        value: Any = None
        if state is not None and state.state not in UNSET:
            value = state.attributes.get(self.attribute) if self.attribute else state.state
        if value is None or (isinstance(value, str) and value in UNSET):
            return self.default
        return value

    def plc_value(self, client: type[PlcClient] | PlcClient, source: Any) -> Value:
        """Return the value to write for a state; raise PlcValueError for one that cannot be."""
        kind = client.value_kind(self.point)
        if kind is ValueKind.TEXT and not self.value_map:
            return client.validate_value(self.point, str(source))
        number: int | float | None
        if isinstance(source, bool):
            number = int(source)
        elif isinstance(source, int | float):
            number = source if math.isfinite(source) else None
        else:
            text = str(source).strip()
            mapped = dict((state.casefold(), value) for state, value in self.value_map)
            if text.casefold() in mapped:
                return self._checked(client, kind, mapped[text.casefold()])
            number = _number(text)
            if number is None and not self.value_map:
                number = SWITCHED.get(text.casefold())
        if number is None:
            raise PlcValueError(f"{source!r} is neither a number nor a state of the value map")
        return self._checked(client, kind, scaled(number, self.scale, self.offset))

    def _checked(
        self, client: type[PlcClient] | PlcClient, kind: ValueKind | None, number: int | float
    ) -> Value:
        """Return a number as the point's kind takes it, checked by the vendor."""
        value: Value = number
        if kind is ValueKind.INTEGER or (kind is ValueKind.BOOL and float(number).is_integer()):
            value = round(number)
        elif kind is ValueKind.FLOAT:
            value = float(number)
        return client.validate_value(self.point, value)


def _finite(value: Any) -> float:
    """Return a stored number; raise ValueError for one that is not (`soon`, `.inf`, `.nan`)."""
    number = float(value)
    if not math.isfinite(number):
        raise ValueError(f"{value!r} is no finite number")
    return number


def expose_config(subentry_id: str, title: str, data: Mapping[str, Any]) -> ExposeConfig:
    """Return the expose a subentry's data describes; raise ValueError where it cannot be read.

    The form checked what it stored; a pasted file may hold anything (a cooldown `soon`).
    """
    default = data.get(CONF_DEFAULT)
    value_map = str(data.get(CONF_VALUE_MAP) or "")
    try:
        return ExposeConfig(
            subentry_id=subentry_id,
            title=title,
            entity_id=str(data[CONF_ENTITY_ID]),
            attribute=str(data[CONF_ATTRIBUTE]) if data.get(CONF_ATTRIBUTE) else None,
            point=Point(str(data[CONF_ADDRESS]), str(data[CONF_DATA_TYPE])),
            scale=_finite(data.get(CONF_SCALE, 1.0)),
            offset=_finite(data.get(CONF_OFFSET, 0.0)),
            value_map=parse_state_map(value_map) if value_map.strip() else (),
            cooldown=max(0.0, _finite(data.get(CONF_COOLDOWN, DEFAULT_COOLDOWN))),
            resend=max(0.0, _finite(data.get(CONF_RESEND, 0.0))),
            send_on_start=bool(data.get(CONF_SEND_ON_START, True)),
            default=None if default in (None, "") else str(default),
        )
    except (InvalidPairs, KeyError, TypeError, ValueError) as err:
        raise ValueError(f"{title}: its settings cannot be read ({err!r})") from err


def entry_exposes(
    entry: PlcBridgeConfigEntry, unreadable: list[str] | None = None
) -> dict[str, ExposeConfig]:
    """Return the entry's readable exposes by subentry id; why the others are not: `unreadable`."""
    exposes: dict[str, ExposeConfig] = {}
    for subentry in entry.subentries.values():
        if subentry.subentry_type != SUBENTRY_EXPOSE:
            continue
        try:
            exposes[subentry.subentry_id] = expose_config(
                subentry.subentry_id, subentry.title, subentry.data
            )
        except ValueError as err:
            if unreadable is not None:
                unreadable.append(str(err))
    return exposes


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


def expose_title(data: Mapping[str, Any]) -> str:
    """Return an expose's name: its entity (and attribute), an arrow, the address."""
    source = str(data[CONF_ENTITY_ID])
    if data.get(CONF_ATTRIBUTE):
        source += f" ({data[CONF_ATTRIBUTE]})"
    return f"{source} → {data[CONF_ADDRESS]}"


@callback
def async_follow_renames(hass: HomeAssistant, entry: PlcBridgeConfigEntry) -> CALLBACK_TYPE:
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
