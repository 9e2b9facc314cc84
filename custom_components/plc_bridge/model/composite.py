"""Entities from several points: a cover, valve, climate, light, fan or switch of a machine.

A point of such an entity stores its `role` besides its platform; the points of one device
subentry that share a platform and a name are one entity, each filling the role it names
(`position`, `open`, `target_temperature`, `state`, `command`, ...). That is the table form
too: one row per address, the rows of one entity sharing its name and platform. Every
cover, valve, climate, light and fan point is a part; a switch point is one only when it
names a role (a switch of one address stays as it was). Points stored before roles
existed have none and load as they always did. Every part is an ordinary point: it joins
the coordinator's poll and is written through its one write path.

A role is checked and stored like the single-address kind it resembles (kinds.py): a limit
switch or state like a binary sensor (invert, on/off codes), a command like a button (codes,
pulse), a position read like a sensor and set like a number (linear range), a status like
an enum sensor and a mode like a select (value map). So a part that is only read is read
only unless the user says otherwise, and one that is written must be at a writable address.
"""

from __future__ import annotations

from collections.abc import Collection, Iterable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from homeassistant.const import CONF_DEVICE_CLASS, CONF_NAME

from ..const import CONF_ENTITY, CONF_INVERT, CONF_PLATFORM, CONF_ROLE, CONF_VALUE_MAP
from ..plc import PlcClient, Point
from .conversion import spelled_as_states, stored_pairs
from .kinds import CONF_SUPERVISION, CONF_TRAVEL_TIME, CONTROLS, KINDS, Kind, Role
from .points import point_data
from .poll_classes import POLL_CLASSES

if TYPE_CHECKING:
    from .points import PointConfig

TRAVEL_MIN, TRAVEL_MAX = 1.0, 600.0
"""The travel times a cover or valve may have, in seconds (0 or empty: none)."""


def takes_roles(platform: str) -> bool:
    """True for a platform whose entities can be built from several points."""
    return platform in KINDS and bool(KINDS[platform].roles)


def is_part(platform: str, role: Any) -> bool:
    """True for a point that is a part of an entity of several points."""
    kind = KINDS.get(platform)
    return kind is not None and (kind.parts_only or (bool(kind.roles) and bool(role)))


def role_of(platform: str, role: Any) -> Role | None:
    """Return the description of a part's role, None where the kind has no such role."""
    kind = KINDS.get(platform)
    return None if kind is None else kind.role(str(role or ""))


def as_platform(platform: str, role: Any) -> str:
    """Return the single-address kind a part is checked and stored as (itself if none)."""
    described = role_of(platform, role)
    return platform if described is None else described.checked_as


def written(data: Mapping[str, Any]) -> bool:
    """True for a stored point its entity writes: a control, or a part of a written role."""
    return as_platform(str(data.get(CONF_PLATFORM, "")), data.get(CONF_ROLE)) in CONTROLS


@dataclass(frozen=True, slots=True)
class Composite:
    """One entity built from points: its key (see `composites`) and its parts by role."""

    key: str
    subentry_id: str
    platform: str
    name: str
    parts: Mapping[str, PointConfig]


def group_key(config: PointConfig) -> tuple[str, str, str] | None:
    """Return what the points of one composite entity share, None for a point of its own."""
    if not is_part(config.platform, config.role):
        return None
    return config.subentry_id, config.platform, config.name


def composites(configs: Mapping[str, PointConfig]) -> dict[str, Composite]:
    """Return the composite entities of these points, by the id of each one's first point.

    An entity's key is the `entity` its parts store (given when the machine is saved), so a
    part added or removed later keeps the entity and its history; else its first point's id.
    A role given twice keeps its first point (the import and the forms refuse that case).
    """
    groups: dict[tuple[str, str, str], dict[str, PointConfig]] = {}
    for point_id in sorted(configs):
        config = configs[point_id]
        if (key := group_key(config)) is not None:
            groups.setdefault(key, {})[point_id] = config
    found: dict[str, Composite] = {}
    keys: set[str] = set()
    for (subentry_id, platform, name), members in groups.items():
        parts: dict[str, PointConfig] = {}
        for config in members.values():
            parts.setdefault(config.role or "", config)
        lead = next(iter(members))
        stored = [c.entity for c in members.values() if c.entity]
        entity = stored[0] if stored and stored[0] not in keys else lead
        keys.add(entity)
        found[lead] = Composite(entity, subentry_id, platform, name, parts)
    return found


def assign_entities(points: dict[str, dict[str, Any]]) -> None:
    """Give every part of a machine's points its entity's key, kept from then on.

    A part joins the key its entity's other parts have; a new entity takes its first
    point's id; rows of one entity renamed apart each get a key of their own.
    """
    groups: dict[tuple[str, str], list[str]] = {}
    for point_id in sorted(points):
        data = points[point_id]
        if is_part(str(data.get(CONF_PLATFORM, "")), data.get(CONF_ROLE)):
            groups.setdefault((data[CONF_PLATFORM], data[CONF_NAME]), []).append(point_id)
    used: set[str] = set()
    for ids in groups.values():
        stored = [str(points[pid][CONF_ENTITY]) for pid in ids if points[pid].get(CONF_ENTITY)]
        key = stored[0] if stored and stored[0] not in used else ids[0]
        used.add(key)
        for point_id in ids:
            points[point_id] = {**points[point_id], CONF_ENTITY: key}


def touched(
    changed: Collection[str], old: Mapping[str, PointConfig], new: Mapping[str, PointConfig]
) -> set[str]:
    """Return the changed point ids and every point of the entities they belong to, then or now.

    An edited part rebuilds its whole entity, and the entity of a removed part too.
    """
    keys = {
        key
        for configs in (old, new)
        for point_id in changed
        if point_id in configs and (key := group_key(configs[point_id])) is not None
    }
    return set(changed) | {
        point_id
        for configs in (old, new)
        for point_id, config in configs.items()
        if group_key(config) in keys
    }


def part_errors(platform: str, values: Mapping[str, Any]) -> dict[str, str]:
    """Check a part's role and its value map's labels; return the errors by field."""
    described = role_of(platform, values.get(CONF_ROLE))
    if described is None:
        return {CONF_ROLE: "role_invalid"}
    if described.labels and not values.get(CONF_VALUE_MAP):
        return {CONF_VALUE_MAP: "map_empty"}
    if described.labels:
        labels = {label for _, label in stored_pairs(values, CONF_VALUE_MAP)}
        if not labels <= set(described.labels):
            return {CONF_VALUE_MAP: "role_labels"}
    return {}


def part_data(
    client: type[PlcClient], values: Mapping[str, Any]
) -> tuple[dict[str, Any], dict[str, str], dict[str, str]]:
    """Check one part as the kind its role resembles; return its data, errors, placeholders."""
    platform = str(values.get(CONF_PLATFORM, ""))
    role = str(values.get(CONF_ROLE) or "")
    described = role_of(platform, role)
    if described is not None and described.labels and values.get(CONF_VALUE_MAP):
        value_map = spelled_as_states(str(values[CONF_VALUE_MAP]), described.labels)
        values = {**values, CONF_VALUE_MAP: value_map}
    errors = part_errors(platform, values)
    kind = KINDS.get(platform)
    own_class = _own_class(kind, values)
    if own_class:  # the entity's own device class, not one of the kind it is checked as
        values = {key: value for key, value in values.items() if key != CONF_DEVICE_CLASS}
    wording = {"role": role, "platform": platform}
    wording["roles"] = ", ".join(kind.role_keys if kind else ())
    wording["labels"] = ", ".join(described.labels if described else ())
    if CONF_ROLE in errors:
        return {}, errors, wording
    data, found, placeholders = point_data(
        client, {**values, CONF_PLATFORM: as_platform(platform, role)}
    )
    placeholders = wording | placeholders
    if described and described.invertible and values.get(CONF_INVERT):
        data[CONF_INVERT] = True
    travel, wrong = travel_data(platform, values)
    supervision, wrong_time = supervision_data(platform, values)
    data |= travel | supervision | {CONF_PLATFORM: platform, CONF_ROLE: role}
    data |= {CONF_DEVICE_CLASS: own_class} if own_class else {}
    wrong |= wrong_time
    return data, errors | found | wrong, placeholders


def _own_class(kind: Kind | None, values: Mapping[str, Any]) -> str:
    """Return a part's device class where it is one of its entity's kind (a cover's shutter)."""
    return "" if kind is None else kind.own_class(values.get(CONF_DEVICE_CLASS))


def travel_data(platform: str, values: Mapping[str, Any]) -> tuple[dict[str, Any], dict[str, str]]:
    """Return what a part stores of its entity's travel time (0 or empty: nothing), or the error.

    Only a cover or a valve travels; its time is bounded, so a level command is always released.
    """
    return _entity_seconds(CONF_TRAVEL_TIME, platform, values)


def supervision_data(
    platform: str, values: Mapping[str, Any]
) -> tuple[dict[str, Any], dict[str, str]]:
    """Return what a part stores of its entity's supervision time (0 or empty: nothing), or why not.

    The bounds are the travel time's: a cover's or valve's travel time is its supervision time.
    """
    return _entity_seconds(CONF_SUPERVISION, platform, values)


def entity_time(platform: str) -> str:
    """Return the time setting an entity of this kind has (travel or supervision), or ""."""
    kind = KINDS.get(platform)
    return "" if kind is None else kind.entity_time


def _entity_seconds(
    key: str, platform: str, values: Mapping[str, Any]
) -> tuple[dict[str, Any], dict[str, str]]:
    """Return an entity's time setting `key` as stored, or its error (`<key>_not_here`, ...)."""
    given = values.get(key)
    if given is None or given == "":
        return {}, {}
    try:
        seconds = float(given)
    except (TypeError, ValueError):
        return {}, {key: f"{key}_out_of_range"}
    if seconds == 0:
        return {}, {}
    if entity_time(platform) != key:
        return {}, {key: f"{key}_not_here"}
    if not TRAVEL_MIN <= seconds <= TRAVEL_MAX:
        return {}, {key: f"{key}_out_of_range"}
    return {key: seconds}, {}


def group_errors(rows: Iterable[Mapping[str, Any]]) -> list[tuple[str, str, dict[str, str]]]:
    """Check the parts of new composite entities together: each role once, one that shows.

    Their travel times and supervision times, where given, agree.

    Returns (entity name, error key, placeholders) for each entity at fault.
    """
    groups: dict[tuple[str, str], list[str]] = {}
    times: dict[tuple[str, str], set[float]] = {}
    watched: dict[tuple[str, str], set[float]] = {}  # supervision times
    for data in rows:
        platform = str(data.get(CONF_PLATFORM, ""))
        if is_part(platform, data.get(CONF_ROLE)):
            key = (platform, str(data[CONF_NAME]))
            groups.setdefault(key, []).append(str(data.get(CONF_ROLE, "")))
            if data.get(CONF_TRAVEL_TIME):
                times.setdefault(key, set()).add(float(data[CONF_TRAVEL_TIME]))
            if data.get(CONF_SUPERVISION):
                watched.setdefault(key, set()).add(float(data[CONF_SUPERVISION]))
    errors: list[tuple[str, str, dict[str, str]]] = []
    for (platform, name), roles in groups.items():
        repeated = sorted({role for role in roles if roles.count(role) > 1})
        if repeated:
            errors.append((name, "role_repeated", {"name": name, "role": repeated[0]}))
        elif len(times.get((platform, name), ())) > 1:
            seconds = ", ".join(f"{time:g}" for time in sorted(times[(platform, name)]))
            errors.append((name, "travel_time_differs", {"name": name, "seconds": seconds}))
        elif len(watched.get((platform, name), ())) > 1:
            seconds = ", ".join(f"{time:g}" for time in sorted(watched[(platform, name)]))
            errors.append((name, "supervision_differs", {"name": name, "seconds": seconds}))
        elif not set(roles) & set(KINDS[platform].needs_one_of):
            needs = ", ".join(KINDS[platform].needs_one_of)
            errors.append((name, "role_missing", {"name": name, "roles": needs}))
    return errors


def point_classes(
    configs: Mapping[str, PointConfig], every_poll: Iterable[Point] = ()
) -> dict[Point, str]:
    """Return each point's poll class; the parts of one entity share their fastest one.

    The points `every_poll` names (machines' data-valid addresses) get none: every poll reads
    them, whatever class a point showing the same address has.
    """
    classes: dict[Point, str] = {}
    for config in configs.values():
        known = classes.get(config.point, config.poll)
        classes[config.point] = min(known, config.poll, key=POLL_CLASSES.index)
    for composite in composites(configs).values():
        parts = [config.point for config in composite.parts.values()]
        shared = min((classes[point] for point in parts), key=POLL_CLASSES.index)
        classes |= dict.fromkeys(parts, shared)
    for point in every_poll:
        classes.pop(point, None)
    return classes
