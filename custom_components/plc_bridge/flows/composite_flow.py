"""The device flow's steps that add an entity from several addresses (composite.py).

The kind is picked from a menu; then one page, built from the kind's description
(model/kinds.py), asks everything: the name and the kind's own device class and time first,
then a section per function (a cover's commands, position, limits, tilt) with, for each role,
its address, its data type and the settings of its own (a limit switch's invert, a mode's
map), and once for the section what its roles share (the commands' pulse, the temperatures'
unit and scale, a position's raw range); the poll class and availability fold away at the end.
The parts join the machine's points only when every part and the whole entity pass the checks
of the import (each part is checked as the single-address kind it resembles).
Editing a part asks its address and data type again, checked the same way, then its settings;
it keeps its point id and its entity's key, so the entity keeps its unique id and entity id.
"""

from __future__ import annotations

from collections.abc import Awaitable, Callable, Iterable, Mapping
import secrets
from typing import Any

from homeassistant.config_entries import SubentryFlowResult
from homeassistant.const import CONF_DEVICE_CLASS, CONF_NAME, CONF_UNIT_OF_MEASUREMENT
from homeassistant.data_entry_flow import section
from homeassistant.helpers.selector import (
    BooleanSelector,
    NumberSelector,
    NumberSelectorConfig,
    NumberSelectorMode,
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
    TextSelector,
    TextSelectorConfig,
)
from homeassistant.helpers.translation import async_get_translations
import voluptuous as vol

from ..const import (
    CONF_ADDRESS,
    CONF_DATA_TYPE,
    CONF_ENTITY,
    CONF_INVERT,
    CONF_MAX,
    CONF_MIN,
    CONF_OFFSET,
    CONF_PLATFORM,
    CONF_PULSE,
    CONF_RAW_MAX,
    CONF_RAW_MIN,
    CONF_READ_ONLY,
    CONF_ROLE,
    CONF_SCALE,
    CONF_SHOWN_MAX,
    CONF_SHOWN_MIN,
    CONF_STEP,
    CONF_VALUE_MAP,
    DOMAIN,
    PULSE_MAX,
    PULSE_MIN,
    SUBENTRY_DEVICE,
)
from ..model.availability import (
    CONF_AVAILABILITY_POLICY,
    check_policy,
    has_data_valid,
    policy_field,
)
from ..model.composite import (
    as_platform,
    group_errors,
    part_data,
    supervision_data,
    travel_data,
)
from ..model.device_classes import unit_selector
from ..model.kinds import (
    COMPOSITE_PLATFORMS,
    CONF_SUPERVISION,
    CONF_TRAVEL_TIME,
    CONTROLS,
    KINDS,
    Kind,
    Role,
)
from ..model.point_table import first_type
from ..model.points import check_point, data_type_selector, point_key
from ..model.poll_classes import CONF_POLL, NORMAL, poll_field
from ..model.write_rules import layout_conflicts
from ..plc import PlcClient, Point
from .base import DeviceFlowBase
from .flow_lists import PointWords, async_point_words, filled

_NUMBER = NumberSelector(NumberSelectorConfig(mode=NumberSelectorMode.BOX, step="any"))

TYPE_SUFFIX = "_data_type"
"""A part's data type field: its role's name and this."""
OPTIONS = "entity_options"
"""The folded section of the entity's page: its poll class and availability."""
PERCENT = {CONF_SHOWN_MIN: 0.0, CONF_SHOWN_MAX: 100.0}
"""What a raw range maps onto for a role read or set in percent."""
ENTITY_KEYS = (
    *(CONF_NAME, CONF_PLATFORM, CONF_ROLE, CONF_ADDRESS, CONF_DATA_TYPE, CONF_READ_ONLY),
    *(CONF_POLL, CONF_AVAILABILITY_POLICY, CONF_TRAVEL_TIME, CONF_SUPERVISION, CONF_ENTITY),
)
"""What the entity's page sets on every part, whatever the role."""
SETTINGS: dict[str, Any] = {
    CONF_PULSE: NumberSelector(
        NumberSelectorConfig(
            min=PULSE_MIN,
            max=PULSE_MAX,
            step=0.1,
            mode=NumberSelectorMode.BOX,
            unit_of_measurement="s",
        )
    ),
    CONF_INVERT: BooleanSelector(),
    CONF_VALUE_MAP: TextSelector(TextSelectorConfig(multiline=True)),
    CONF_UNIT_OF_MEASUREMENT: unit_selector("sensor", "temperature"),
    **dict.fromkeys(
        (CONF_SCALE, CONF_OFFSET, CONF_MIN, CONF_MAX, CONF_RAW_MIN, CONF_RAW_MAX), _NUMBER
    ),
    CONF_STEP: NumberSelector(NumberSelectorConfig(min=0, mode=NumberSelectorMode.BOX, step="any")),
}
"""The field of each setting a role asks or its section shares (model/kinds.py names them)."""
SECTIONS = tuple(dict.fromkeys(role.section for kind in KINDS.values() for role in kind.roles))
"""Every section an entity's page may have."""
PLACEHOLDERS = (
    "error", "name", "role", "address", "data_type", "roles", "point", "written", "pair",
    "units", "labels", "seconds", "platform", "kind", "needs", "title",
    *(f"{name}_{what}" for name in (*SECTIONS, OPTIONS) for what in ("role", "problem")),
)  # fmt: skip
"""What the entity page's texts and errors may name; each is given, empty when unused."""


class CompositeSteps(DeviceFlowBase):
    """Steps of the device flow for an entity of several points (its handler's base)."""

    @property
    def _data_valid(self) -> bool:
        """True when the machine names a data-valid address (its entities may follow it)."""
        return has_data_valid(self._availability)

    async def async_step_composite(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """The kind of entity: a menu, its page follows."""
        return self.async_show_menu(
            step_id="composite",
            menu_options=[f"entity_{platform}" for platform in COMPOSITE_PLATFORMS],
        )

    async def async_add_entity(self, platform: str) -> SubentryFlowResult:
        """Open the page of a new entity of this kind."""
        self._composite, self._edited = {CONF_PLATFORM: platform}, {}
        return await self.async_step_composite_entity()

    async def async_edit_part(self, point_id: str) -> SubentryFlowResult:
        """Edit the entity a part belongs to, on its page; its parts keep their point ids."""
        entity = entity_of(self._points[point_id])
        self._edited = {
            str(data.get(CONF_ROLE)): pid
            for pid, data in self._points.items()
            if entity_of(data) == entity
        }
        self._composite = {CONF_PLATFORM: entity[0]}
        return await self.async_step_composite_entity()

    async def async_step_composite_entity(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """The entity's one page: its name, then each section's roles and settings."""
        kind = KINDS[self._composite[CONF_PLATFORM]]
        words = await async_point_words(self.hass)
        errors: dict[str, str] = {}
        placeholders = dict.fromkeys(PLACEHOLDERS, "")
        placeholders["kind"] = words.kinds.get(kind.key, kind.key)
        placeholders["needs"] = ", ".join(words.roles.get(r, r) for r in kind.needs_one_of)
        stored = {role: self._points[pid] for role, pid in self._edited.items()}
        name = next(iter(stored.values()))[CONF_NAME] if stored else ""
        placeholders["title"] = filled(words.page["edit" if stored else "new"], {
            "kind": placeholders["kind"], "name": name
        })  # fmt: skip
        if user_input is not None:
            values = flattened(user_input)
            roles: dict[str, str] = {}
            parts = self._entity_parts(kind, values, errors, placeholders, roles)
            if not errors:
                self._keep(parts)
                return await self.async_step_menu()
            await self._word_sections(errors, placeholders, roles, words)
        return self.async_show_form(
            step_id="composite_entity",
            data_schema=self.add_suggested_values_to_schema(
                self._entity_schema(kind, errors), user_input or page_values(kind, stored)
            ),
            errors=errors,
            description_placeholders=placeholders,
        )

    def _keep(self, parts: list[dict[str, Any]]) -> None:
        """Store the page's parts: an edited role keeps its point id, a cleared one goes."""
        kept = [
            {**part, CONF_ENTITY: self._points[pid][CONF_ENTITY]}
            if (pid := self._edited.get(part[CONF_ROLE])) and CONF_ENTITY in self._points[pid]
            else part
            for part in parts
        ]
        for pid in self._edited.values():
            del self._points[pid]
        for part in kept:
            self._points[self._edited.get(part[CONF_ROLE]) or secrets.token_hex(6)] = part
        self._composite, self._edited = {}, {}

    def _entity_schema(self, kind: Kind, errors: Mapping[str, str]) -> vol.Schema:
        """Return the entity's page: name, own class and time, a section per function."""
        fields: dict[vol.Marker, Any] = {vol.Required(CONF_NAME): TextSelector()}
        if kind.device_class is not None:
            fields[vol.Optional(CONF_DEVICE_CLASS)] = SelectSelector(
                SelectSelectorConfig(
                    options=list(kind.device_class),
                    translation_key=f"{kind.key}_device_class",
                    mode=SelectSelectorMode.DROPDOWN,
                )
            )
        if kind.entity_time:
            fields[vol.Optional(kind.entity_time)] = _NUMBER
        for name, roles in kind.sections.items():
            inner: dict[vol.Marker, Any] = {}
            for role in roles:
                inner[vol.Optional(role.key)] = TextSelector()
                inner[vol.Optional(f"{role.key}{TYPE_SUFFIX}")] = data_types(self._client)
                for setting in role.asks:
                    inner[_setting_marker(f"{role.key}_{setting}", setting)] = SETTINGS[setting]
            for setting in kind.shared(name):
                inner[_setting_marker(setting, setting)] = SETTINGS[setting]
            folded = name not in kind.open_sections and name not in errors
            fields[vol.Optional(name, default={})] = section(
                vol.Schema(inner), {"collapsed": folded}
            )
        options = {**poll_field(), **policy_field(data_valid=self._data_valid)}
        folded = OPTIONS not in errors
        fields[vol.Optional(OPTIONS, default={})] = section(
            vol.Schema(options), {"collapsed": folded}
        )
        return vol.Schema(fields)

    def _entity_parts(
        self,
        kind: Kind,
        values: Mapping[str, Any],
        errors: dict[str, str],
        placeholders: dict[str, str],
        roles: dict[str, str],
    ) -> list[dict[str, Any]]:
        """Check the page's values as the import checks them; return the parts, or errors.

        Home Assistant's frontend shows a section's errors at the section, not at its fields:
        an error of a role or setting is the section's; `roles` gets the role at fault.
        """
        name = str(values.get(CONF_NAME) or "").strip()
        taken = any(
            (data[CONF_NAME], data[CONF_PLATFORM]) == (name, kind.key)
            for pid, data in self._points.items()
            if pid not in self._edited.values()
        )
        if not name:
            errors[CONF_NAME] = "name_required"
        elif taken:
            errors[CONF_NAME] = "composite_name_taken"
        entity: dict[str, Any] = {CONF_NAME: name, CONF_PLATFORM: kind.key}
        entity[CONF_POLL] = values.get(CONF_POLL, NORMAL)
        policy, wrong = check_policy(values, data_valid=self._data_valid)
        entity |= policy
        if wrong:
            errors[OPTIONS] = wrong
        if values.get(CONF_DEVICE_CLASS):
            entity[CONF_DEVICE_CLASS] = values[CONF_DEVICE_CLASS]
        for seconds, wrong_time in (
            travel_data(kind.key, values),
            supervision_data(kind.key, values),
        ):
            entity |= seconds
            errors |= wrong_time
        self._composite = {**entity, CONF_NAME: name or "-"}
        parts: list[dict[str, Any]] = []
        taken_points = self._taken()
        for role in kind.roles:
            address = str(values.get(role.key) or "").strip()
            if not address or errors.get(role.section):
                continue
            data_type = str(values.get(f"{role.key}{TYPE_SUFFIX}") or "")
            given = taken_points | {point_key(part) for part in parts}
            at, found, details = self._part_at(role.key, address, data_type, given)
            if at is not None:
                settings = {CONF_READ_ONLY: not role.written} | _settings(role, values)
                kept = self._unasked(kind, role)
                made, found, details = part_data(self._client, kept | at | settings)
                made |= policy  # the point checks leave it out: it is the entity's
            if found or at is None:
                errors[role.section] = next(iter(found.values()))
                placeholders |= details
                roles[role.section] = role.key
                continue
            parts.append(made)
        if errors:
            return []
        if not parts:  # nothing given: an entity needs a part that shows it
            errors["base"] = "role_missing"
            placeholders |= {CONF_NAME: name, "roles": placeholders["needs"]}
            return []
        if problems := group_errors(parts):
            errors["base"] = problems[0][1]
            placeholders |= problems[0][2]
            placeholders["roles"] = placeholders["needs"]
            return []
        for conflict, key, found_words in self._layout_errors(parts, []):
            described = kind.role(str(conflict[CONF_ROLE]))
            name = described.section if described else "base"
            errors.setdefault(name, key)
            roles.setdefault(name, str(conflict[CONF_ROLE]))
            placeholders |= found_words
        return [] if errors else parts

    def _unasked(self, kind: Kind, role: Role) -> dict[str, Any]:
        """Return what an edited role's stored part holds that its page does not ask.

        Its on and off codes, a precision, ...: kept, and checked again with the page's values.
        """
        pid = self._edited.get(role.key)
        if pid is None:
            return {}
        asked = {*ENTITY_KEYS, *role.asks, *role.shares, *(PERCENT if role.percent else ())}
        asked |= {CONF_DEVICE_CLASS} if kind.device_class is not None else set()
        return {k: v for k, v in self._points[pid].items() if k not in asked}

    async def _word_sections(
        self,
        errors: dict[str, str],
        placeholders: dict[str, str],
        roles: Mapping[str, str],
        words: PointWords,
    ) -> None:
        """Give each section's error the words of its message, named by its role.

        A section's error is shown at the section's top: `in_<section>` reads "Open command:"
        and the message the field would have had, in Home Assistant's language.
        """
        language = self.hass.config.language
        texts = await async_get_translations(self.hass, language, "config_subentries", [DOMAIN])
        prefix = f"component.{DOMAIN}.config_subentries.{SUBENTRY_DEVICE}.error."
        for name in (*SECTIONS, OPTIONS):
            if name not in errors:
                continue
            message = texts.get(prefix + errors[name], errors[name])
            role = words.roles.get(roles.get(name, ""), "")
            placeholders[f"{name}_role"] = role[:1].upper() + role[1:]
            placeholders[f"{name}_problem"] = filled(message, placeholders)
            errors[name] = f"in_{name}"

    def _part_at(
        self, role: str, address: str, data_type: str, taken: set[Point]
    ) -> tuple[dict[str, Any] | None, dict[str, str], dict[str, str]]:
        """Check a part's address and data type (empty: the first that fits) as its role's kind.

        Returns the part (None when refused), the errors by field and their placeholders.
        """
        fitting = first_type(self._client, address.strip())
        values = {**self._composite, CONF_ROLE: role, CONF_ADDRESS: address.strip()}
        values[CONF_DATA_TYPE] = data_type.strip() or fitting
        shown = as_platform(self._composite[CONF_PLATFORM], role)
        point, _, found, details = check_point(self._client, {**values, CONF_PLATFORM: shown})
        if point is None and check_point(self._client, {**values, CONF_DATA_TYPE: fitting})[0]:
            found = {CONF_DATA_TYPE: "invalid_data_type"}  # the address is good, not its type
        if point is not None and point in taken:
            found[CONF_ADDRESS] = "already_configured"
        if error := found.pop(CONF_PLATFORM, None):  # the kind a part needs: its type's fault
            found[CONF_ADDRESS if error == "address_not_writable" else CONF_DATA_TYPE] = error
        if found or point is None:
            return None, found, details
        return {**values, CONF_ADDRESS: point.address, CONF_DATA_TYPE: point.data_type}, {}, {}

    def _layout_errors(
        self, new: list[dict[str, Any]], others: list[dict[str, Any]]
    ) -> list[tuple[Mapping[str, Any], str, dict[str, str]]]:
        """Return the new parts whose writes would meet read-only data, with error and details.

        A part not made yet is as read only as its role's kind is by default.
        """
        return layout_errors(
            self._client, [*self._plc_points(), *map(defaulted, others)], map(defaulted, new)
        )

    def removal_errors(self, chosen: list[str]) -> tuple[dict[str, str], dict[str, str]]:
        """Refuse to remove parts of an entity that leave it none that shows (all may go)."""
        entities = {entity_of(self._points[point_id]) for point_id in chosen}
        left = [
            data
            for point_id, data in self._points.items()
            if point_id not in chosen and entity_of(data) in entities
        ]
        for _name, error, placeholders in group_errors(left):
            if error == "role_missing":
                return {"base": "role_left_missing"}, placeholders
        return {}, {}


def page_values(kind: Kind, parts: Mapping[str, Mapping[str, Any]]) -> dict[str, Any]:
    """Return an entity's stored parts as its page shows them, each field in its section."""
    if not parts:
        return {}
    first = next(iter(parts.values()))
    values: dict[str, Any] = {CONF_NAME: first[CONF_NAME]}
    for stored in parts.values():
        if own := kind.own_class(stored.get(CONF_DEVICE_CLASS)):
            values.setdefault(CONF_DEVICE_CLASS, own)
        if kind.entity_time and stored.get(kind.entity_time):
            values.setdefault(kind.entity_time, stored[kind.entity_time])
    for name, roles in kind.sections.items():
        shown: dict[str, Any] = {}
        for role in roles:
            if (part := parts.get(role.key)) is None:
                continue
            shown |= {
                role.key: part[CONF_ADDRESS],
                f"{role.key}{TYPE_SUFFIX}": part[CONF_DATA_TYPE],
            }
            shown |= {f"{role.key}_{s}": part[s] for s in role.asks if s in part}
            for setting in role.shares:
                if setting in part:
                    shown.setdefault(setting, part[setting])
        values[name] = shown
    options = {CONF_POLL: first.get(CONF_POLL, NORMAL)}
    options |= {k: first[k] for k in (CONF_AVAILABILITY_POLICY,) if k in first}
    return values | {OPTIONS: options}


def flattened(user_input: Mapping[str, Any]) -> dict[str, Any]:
    """Return a page's values with its sections' fields at the top (their names are unique)."""
    values: dict[str, Any] = {}
    for key, value in user_input.items():
        values |= dict(value) if isinstance(value, Mapping) else {key: value}
    return values


def _setting_marker(key: str, setting: str) -> vol.Marker:
    """Return a setting's field: a switch defaults to off, the others may stay empty."""
    if setting == CONF_INVERT:
        return vol.Required(key, default=False)
    return vol.Optional(key)


def _settings(role: Role, values: Mapping[str, Any]) -> dict[str, Any]:
    """Return what a role takes from the page: its own settings and its section's shared ones."""
    taken = {s: values.get(f"{role.key}_{s}") for s in role.asks}
    taken |= {s: values.get(s) for s in role.shares}
    taken = {key: value for key, value in taken.items() if value not in (None, "")}
    if role.percent and ({CONF_RAW_MIN, CONF_RAW_MAX} & set(taken)):
        taken |= PERCENT
    return taken


def _entity_step(platform: str) -> Callable[[CompositeSteps, Any], Awaitable[SubentryFlowResult]]:
    """Return the menu's step that opens a new entity of this kind."""

    async def step(self: CompositeSteps, user_input: Any = None) -> SubentryFlowResult:
        """Open the page of a new entity of the kind."""
        return await self.async_add_entity(platform)

    return step


for _platform in COMPOSITE_PLATFORMS:
    setattr(CompositeSteps, f"async_step_entity_{_platform}", _entity_step(_platform))


def data_types(client: type[PlcClient]) -> SelectSelector:
    """Return a part's data type field: the vendor's types, or one typed (its parser checks it)."""
    return data_type_selector(client)


def defaulted(data: Mapping[str, Any]) -> Mapping[str, Any]:
    """Return a point's data with its read-only flag, as its form would default it if unset."""
    if CONF_READ_ONLY in data:
        return data
    shown = as_platform(str(data.get(CONF_PLATFORM, "")), data.get(CONF_ROLE))
    return {**data, CONF_READ_ONLY: shown not in CONTROLS}


def layout_errors(
    client: type[PlcClient], known: Iterable[Mapping[str, Any]], new: Iterable[Mapping[str, Any]]
) -> list[tuple[Mapping[str, Any], str, dict[str, str]]]:
    """Return each new point whose writes would meet read-only data: its form error and details.

    Where the point is the read-only one itself (another spelling), it is configured already.
    """
    return [
        (
            data,
            "already_configured" if found.key == "read_only" else found.key,
            {"written": found.point.address, "point": found.other.address if found.other else ""},
        )
        for data, found in layout_conflicts(client, known, new)
    ]


def entity_of(data: dict[str, Any]) -> tuple[str, str]:
    """Return what the rows of one entity share in a machine: its platform and name."""
    return str(data.get(CONF_PLATFORM, "")), str(data.get(CONF_NAME, ""))
