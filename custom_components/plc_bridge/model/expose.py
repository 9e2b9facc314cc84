"""What one expose is: its stored settings, the PLC value a state becomes, its running state.

An expose subentry stores the entity (and optionally one of its attributes), the PLC address
and data type, and how the state is converted: a value map (`on=1;off=0`, `home=1;not_home=0`)
names the PLC value of a state; any other state is taken as a number, written as
number × scale + offset. Without a map, `on`/`off` and `true`/`false` mean 1 and 0.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
import math
import re
from typing import Any

from homeassistant.config_entries import ConfigEntry
from homeassistant.const import CONF_ATTRIBUTE, CONF_ENTITY_ID, STATE_UNAVAILABLE, STATE_UNKNOWN
from homeassistant.core import HomeAssistant, State
from homeassistant.helpers import entity_registry as er

from ..const import (
    CONF_ADDRESS,
    CONF_COOLDOWN,
    CONF_DATA_TYPE,
    CONF_DEFAULT,
    CONF_OFFSET,
    CONF_RESEND,
    CONF_SCALE,
    CONF_SEND_ON_START,
    CONF_VALUE_MAP,
    CONF_VENDOR,
    DOMAIN,
    SUBENTRY_EXPOSE,
)
from ..plc import PlcAddressError, PlcClient, PlcError, PlcValueError, Point, Value, ValueKind
from ..plc.vendors import client_class
from .conversion import InvalidPairs, pair_parts, scaled
from .points import PointConfig, entry_points
from .write_rules import ReadOnlyPoints, writable

type StateMap = tuple[tuple[str, int | float], ...]
"""States (as typed) and the PLC value each is written as."""
UNSET = frozenset({STATE_UNAVAILABLE, STATE_UNKNOWN})
SWITCHED = {"on": 1, "off": 0, "true": 1, "false": 0}
"""What the states of a switch or binary sensor write where no value map is given."""
DEFAULT_COOLDOWN = 1.0
"""Seconds between two writes of one expose unless the user sets otherwise."""
CONF_SEND = "send"
"""Expose data: false while the expose must not write (one pasted from a file); absent: true."""
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
    send: bool = True
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
            send=bool(data.get(CONF_SEND, True)),
            default=None if default in (None, "") else str(default),
        )
    except (InvalidPairs, KeyError, TypeError, ValueError) as err:
        raise ValueError(f"{title}: its settings cannot be read ({err!r})") from err


COOLDOWN_MIN = 0.1
"""The shortest cooldown, in seconds: a cooldown of 0 would write at every change of the state."""
RESEND_MIN = 1.0
"""The shortest periodic resend, in seconds (0: no resend)."""

type Checked = tuple[dict[str, Any], dict[str, str], dict[str, str]]
"""The data to store, the errors by field, and the words their messages name."""


def check_expose(
    client: type[PlcClient],
    values: Mapping[str, Any],
    *,
    read_only: Sequence[Point] = (),
    taken: Sequence[Point] = (),
    feeds_back: Callable[[Point, str], bool] | None = None,
) -> Checked:
    """Check an expose as every door must (form, file, action): the one validation of an expose.

    `read_only`: the PLC's points marked read only; `taken`: the addresses of its other
    exposes; `feeds_back(point, entity_id)`: whether writing the point comes back to the
    entity through our entities and exposes (None where the entities do not exist yet).
    """
    placeholders = {"error": "", CONF_ADDRESS: str(values.get(CONF_ADDRESS, ""))}
    try:
        point = client.validate_point(
            Point(str(values[CONF_ADDRESS]).strip(), str(values[CONF_DATA_TYPE]).strip())
        )
    except PlcAddressError as err:
        return {}, {CONF_ADDRESS: "invalid_address"}, placeholders | {"error": str(err)}
    placeholders[CONF_ADDRESS] = point.address
    errors: dict[str, str] = {}
    if client.value_kind(point) not in SENDABLE:
        errors[CONF_DATA_TYPE] = "expose_data_type"
    elif not client.address_writable(point):
        errors[CONF_ADDRESS] = "address_not_writable"
    elif _covers(client, read_only, point):
        errors[CONF_ADDRESS] = "expose_read_only"
    elif _covers(client, taken, point):
        errors[CONF_ADDRESS] = "already_configured"
    elif feeds_back is not None and feeds_back(point, str(values[CONF_ENTITY_ID])):
        errors[CONF_ADDRESS] = "expose_feeds_back"
    data: dict[str, Any] = {
        CONF_ENTITY_ID: str(values[CONF_ENTITY_ID]),
        CONF_ADDRESS: point.address,
        CONF_DATA_TYPE: point.data_type,
        CONF_SCALE: float(values.get(CONF_SCALE, 1.0)),
        CONF_OFFSET: float(values.get(CONF_OFFSET, 0.0)),
        CONF_COOLDOWN: float(values.get(CONF_COOLDOWN, DEFAULT_COOLDOWN)),
        CONF_RESEND: float(values.get(CONF_RESEND, 0.0)),
        CONF_SEND_ON_START: bool(values.get(CONF_SEND_ON_START, True)),
    }
    if not bool(values.get(CONF_SEND, True)):
        data[CONF_SEND] = False
    if attribute := str(values.get(CONF_ATTRIBUTE) or "").strip():
        data[CONF_ATTRIBUTE] = attribute
    if data[CONF_SCALE] == 0:
        errors[CONF_SCALE] = "scale_zero"
    if not data[CONF_COOLDOWN] >= COOLDOWN_MIN:
        errors[CONF_COOLDOWN] = "cooldown_too_short"
    if data[CONF_RESEND] != 0 and not data[CONF_RESEND] >= RESEND_MIN:
        errors[CONF_RESEND] = "resend_too_short"
    if text := str(values.get(CONF_VALUE_MAP) or "").strip():
        try:
            data[CONF_VALUE_MAP] = format_state_map(parse_state_map(text))
        except InvalidPairs as err:
            errors[CONF_VALUE_MAP] = err.key
            placeholders["pair"] = err.text
    if (default := str(values.get(CONF_DEFAULT) or "").strip()) and not errors:
        data[CONF_DEFAULT] = default
        try:
            expose_config("", "", data).plc_value(client, default)
        except PlcError as err:
            errors[CONF_DEFAULT] = "invalid_default"
            placeholders["error"] = str(err)
    return data, errors, placeholders


def _covers(client: type[PlcClient], points: Sequence[Point], point: Point) -> bool:
    """True when writing the point would meet one of the points (as the write guard sees it)."""
    return not writable(client, point) or ReadOnlyPoints(client, points).conflict(point) is not None


def entity_key(config: PointConfig) -> str:
    """Return the end of the unique id of the entity that shows a point (its entity's key)."""
    return config.entity or config.point_id


def readers(hass: HomeAssistant, entry: ConfigEntry[Any], point: Point) -> set[str]:
    """Return the entity ids of the entry's entities that show data the point covers."""
    client = client_class(entry.data[CONF_VENDOR])
    keys = {
        entity_key(config)
        for config in entry_points(entry).values()
        if _covers(client, [config.point], point)
    }
    if not keys:
        return set()
    registered = er.async_entries_for_config_entry(er.async_get(hass), entry.entry_id)
    return {
        reg.entity_id
        for reg in registered
        if any(re.sub(r"_bit\d+$", "", reg.unique_id).endswith(f"_{key}") for key in keys)
    }


def feeds_back(
    hass: HomeAssistant, entry: ConfigEntry[Any], point: Point, entity_id: str, editing: str | None
) -> bool:
    """True when writing the point of the entry comes back to the entity, at any depth.

    The graph: a written address -> our entities (of any PLC entry) showing it -> the exposes
    that send those entities (and send) -> the addresses they write -> ... An expose closing a
    cycle would write again at each change, never settling (a scale runs away).
    """
    entries = {item.entry_id: item for item in hass.config_entries.async_entries(DOMAIN)}
    entries[entry.entry_id] = entry
    sending = [
        (item, config)
        for item in entries.values()
        for sid, config in entry_exposes(item).items()
        if config.send and not (item.entry_id == entry.entry_id and sid == editing)
    ]
    todo, seen = [(entry, point)], set[str]()
    while todo:
        written_entry, written = todo.pop()
        for reader in readers(hass, written_entry, written):
            if reader == entity_id:
                return True
            if reader not in seen:
                seen.add(reader)
                todo += [(item, c.point) for item, c in sending if c.entity_id == reader]
    return False


def entry_exposes(
    entry: ConfigEntry[Any], unreadable: list[str] | None = None
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


def expose_title(data: Mapping[str, Any]) -> str:
    """Return an expose's name: its entity (and attribute), an arrow, the address."""
    source = str(data[CONF_ENTITY_ID])
    if data.get(CONF_ATTRIBUTE):
        source += f" ({data[CONF_ATTRIBUTE]})"
    return f"{source} → {data[CONF_ADDRESS]}"
