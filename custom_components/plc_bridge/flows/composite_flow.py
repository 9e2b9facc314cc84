"""The device flow's steps that add an entity from several addresses (composite.py).

The kind and the name first; then an address (and a data type) for each part the kind
has, every one optional; then, part by part, the settings of the single-address kind the
part resembles (a command's pulse, a position's range, a mode's map). The parts join the
machine's points only when every part and the whole entity pass the checks of the import.
Editing a part asks its address and data type again, checked the same way, then its settings;
it keeps its point id and its entity's key, so the entity keeps its unique id and entity id.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
import secrets
from typing import Any

from homeassistant.config_entries import SubentryFlowResult
from homeassistant.const import CONF_NAME
from homeassistant.helpers.selector import (
    BooleanSelector,
    NumberSelector,
    NumberSelectorConfig,
    NumberSelectorMode,
    SelectSelector,
    SelectSelectorConfig,
    TextSelector,
)
import voluptuous as vol

from ..const import (
    CONF_ADDRESS,
    CONF_DATA_TYPE,
    CONF_ENTITY,
    CONF_INVERT,
    CONF_PLATFORM,
    CONF_READ_ONLY,
    CONF_ROLE,
)
from ..model.availability import (
    CONF_AVAILABILITY_POLICY,
    check_policy,
    has_data_valid,
    policy_field,
)
from ..model.composite import (
    as_platform,
    entity_time,
    group_errors,
    part_data,
    role_of,
    supervision_data,
    travel_data,
)
from ..model.kinds import (
    COMPOSITE_PLATFORMS,
    CONF_SUPERVISION,
    CONF_TRAVEL_TIME,
    CONTROLS,
    KINDS,
)
from ..model.point_table import first_type
from ..model.points import check_point, data_type_selector, point_key
from ..model.poll_classes import CONF_POLL, NORMAL, poll_field
from ..model.write_rules import layout_conflicts
from ..plc import PlcAddressError, PlcClient, Point
from .base import DeviceFlowBase
from .point_form import BASE_FIELDS, details_schema

SHARED = (CONF_POLL, CONF_TRAVEL_TIME, CONF_SUPERVISION, CONF_AVAILABILITY_POLICY)
"""What every part of one entity has alike: its poll class, travel and supervision time, and
its availability policy."""
TIMES = (CONF_TRAVEL_TIME, CONF_SUPERVISION)
"""The entity's times the first form (or a part's address form) asks, stored on every part."""
_SECONDS = NumberSelector(NumberSelectorConfig(mode=NumberSelectorMode.BOX, step="any"))

TYPE_SUFFIX = "_data_type"
"""A part's data type field: its role's name and this."""


class CompositeSteps(DeviceFlowBase):
    """Steps of the device flow for an entity of several points (its handler's base)."""

    @property
    def _data_valid(self) -> bool:
        """True when the machine names a data-valid address (its entities may follow it)."""
        return has_data_valid(self._availability)

    async def async_step_composite(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """The kind of entity and its name."""
        errors: dict[str, str] = {}
        if user_input is not None:
            name = str(user_input.get(CONF_NAME, "")).strip()
            platform = str(user_input[CONF_PLATFORM])
            taken = any(
                (data[CONF_NAME], data[CONF_PLATFORM]) == (name, platform)
                for data in self._points.values()
            )
            if not name:
                errors[CONF_NAME] = "name_required"
            elif taken:
                errors[CONF_NAME] = "composite_name_taken"
            else:
                self._composite = {CONF_NAME: name, CONF_PLATFORM: platform}
                self._composite[CONF_POLL] = user_input.get(CONF_POLL, NORMAL)
                policy, wrong = check_policy(user_input, data_valid=self._data_valid)
                self._composite |= policy
                if wrong:
                    errors[CONF_AVAILABILITY_POLICY] = wrong
                else:
                    return await self.async_step_composite_parts()
        schema = vol.Schema(
            {
                vol.Required(CONF_PLATFORM, default="cover"): SelectSelector(
                    SelectSelectorConfig(
                        options=list(COMPOSITE_PLATFORMS), translation_key="composite_platform"
                    )
                ),
                vol.Required(CONF_NAME): TextSelector(),
                **poll_field(),
                **policy_field(data_valid=self._data_valid),
            }
        )
        return self.async_show_form(
            step_id="composite",
            data_schema=self.add_suggested_values_to_schema(schema, user_input or {}),
            errors=errors,
        )

    async def async_step_composite_parts(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """An address (and its data type) for each part of the kind; leave out those it lacks."""
        platform = self._composite[CONF_PLATFORM]
        errors: dict[str, str] = {}
        placeholders = {"error": "", "name": self._composite[CONF_NAME], "role": ""}
        placeholders |= {CONF_ADDRESS: "", CONF_DATA_TYPE: ""}
        placeholders["roles"] = ", ".join(KINDS[platform].role_keys)
        placeholders |= {"point": "", "written": ""}
        if user_input is not None:
            travel, errors = travel_data(platform, user_input)
            supervision, wrong = supervision_data(platform, user_input)
            errors |= wrong
            self._composite = {k: v for k, v in self._composite.items() if k not in TIMES}
            self._composite |= travel | supervision
            parts = self._given(platform, user_input, errors, placeholders)
            problems = group_errors(parts)
            if not errors and problems:
                errors["base"] = problems[0][1]
                placeholders |= problems[0][2]
            for part, key, found in self._layout_errors(parts, []) if not errors else []:
                errors.setdefault(part[CONF_ROLE], key)
                placeholders |= found
            if not errors:
                self._parts, self._made = parts, []
                return await self.async_step_composite_part()
        fields: dict[vol.Marker, Any] = {}
        for role in KINDS[platform].role_keys:
            fields[vol.Optional(role)] = TextSelector()
            fields[vol.Optional(f"{role}{TYPE_SUFFIX}")] = data_types(self._client)
        if time := entity_time(platform):
            fields[vol.Optional(time)] = _SECONDS
        return self.async_show_form(
            step_id="composite_parts",
            data_schema=self.add_suggested_values_to_schema(vol.Schema(fields), user_input or {}),
            errors=errors,
            description_placeholders=placeholders,
        )

    def _given(
        self,
        platform: str,
        user_input: dict[str, Any],
        errors: dict[str, str],
        placeholders: dict[str, str],
    ) -> list[dict[str, Any]]:
        """Return the parts given an address, each checked as the kind it resembles."""
        parts: list[dict[str, Any]] = []
        taken = self._taken()
        for role in KINDS[platform].role_keys:
            address = str(user_input.get(role) or "").strip()
            if not address:
                continue
            data_type = str(user_input.get(f"{role}{TYPE_SUFFIX}") or "")
            given = taken | {point_key(part) for part in parts}
            part, found, details = self._part_at(role, address, data_type, given)
            if part is None:
                errors[role] = next(iter(found.values()))
                placeholders |= details
                continue
            parts.append(part)
        return parts

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

    async def async_step_composite_part(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """The settings of one part, as its resembling kind has them; then the next part."""
        values = self._parts[len(self._made)]
        role, platform = values[CONF_ROLE], values[CONF_PLATFORM]
        errors: dict[str, str] = {}
        placeholders = {"role": role, "units": "", "pair": "", "error": "", "platform": platform}
        placeholders |= {"point": "", "written": ""}
        placeholders |= {key: values[key] for key in (CONF_ADDRESS, CONF_DATA_TYPE, CONF_NAME)}
        if user_input is not None:
            base = {key: values[key] for key in (*BASE_FIELDS, CONF_ROLE, *SHARED) if key in values}
            data, errors, found = part_data(self._client, base | user_input)
            data |= {k: base[k] for k in (CONF_AVAILABILITY_POLICY,) if k in base}
            placeholders |= found
            others = [*self._made, *self._parts[len(self._made) + 1 :]]
            for _part, key, details in self._layout_errors([data], others) if not errors else []:
                errors[CONF_READ_ONLY] = key
                placeholders |= details
            if not errors:
                if values.get(CONF_ENTITY):  # an edited part stays a part of its entity
                    data[CONF_ENTITY] = values[CONF_ENTITY]
                self._made.append(data)
                if len(self._made) < len(self._parts):
                    return await self.async_step_composite_part()
                ids = self._part_ids or [secrets.token_hex(6) for _ in self._made]
                self._points |= dict(zip(ids, self._made, strict=True))
                if self._part_ids:  # an edited part's class and travel are its entity's
                    self._share(self._made[0])
                self._parts, self._made, self._part_ids = [], [], []
                self._editing = None
                return await self.async_step_menu()
        shown = as_platform(platform, role)
        try:
            kind = self._client.value_kind(Point(values[CONF_ADDRESS], values[CONF_DATA_TYPE]))
        except PlcAddressError:
            kind = None
        schema = details_schema(shown, kind)
        schema = vol.Schema({k: v for k, v in schema.schema.items() if k != CONF_POLL})
        if self._part_ids:  # a new entity's parts take the class its first step set
            schema = schema.extend(poll_field())
        if (described := role_of(platform, role)) is not None and described.invertible:
            schema = schema.extend({vol.Required(CONF_INVERT, default=False): BooleanSelector()})
        return self.async_show_form(
            step_id="composite_part",
            data_schema=self.add_suggested_values_to_schema(schema, user_input or values),
            errors=errors,
            description_placeholders=placeholders,
        )

    def _share(self, part: dict[str, Any]) -> None:
        """Give every part of the edited part's entity the part's poll class and travel time."""
        shared = {key: part[key] for key in SHARED if key in part}
        for point_id, data in self._points.items():
            if (data[CONF_NAME], data[CONF_PLATFORM]) == (part[CONF_NAME], part[CONF_PLATFORM]):
                kept = {key: value for key, value in data.items() if key not in SHARED}
                self._points[point_id] = kept | shared

    async def async_edit_part(self, point_id: str) -> SubentryFlowResult:
        """Edit one part: its address and data type, then its settings; its entity stays."""
        data = self._points[point_id]
        self._composite = {CONF_NAME: data[CONF_NAME], CONF_PLATFORM: data[CONF_PLATFORM]}
        self._parts, self._made, self._part_ids = [dict(data)], [], [point_id]
        self._editing = point_id  # its own address is not taken
        return await self.async_step_composite_edit()

    async def async_step_composite_edit(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """A part's address and data type, checked as the import checks them."""
        values = self._parts[0]
        errors: dict[str, str] = {}
        placeholders = {key: str(values[key]) for key in (CONF_NAME, CONF_ROLE, CONF_ADDRESS)}
        placeholders |= {CONF_DATA_TYPE: str(values[CONF_DATA_TYPE]), "error": "", "roles": ""}
        placeholders |= {"point": "", "written": "", "seconds": ""}
        platform = str(values[CONF_PLATFORM])
        if user_input is not None:
            address = str(user_input.get(CONF_ADDRESS) or "")
            data_type = str(user_input.get(CONF_DATA_TYPE) or "")
            travel, errors = travel_data(platform, user_input)
            supervision, wrong = supervision_data(platform, user_input)
            errors |= wrong
            policy, refused = check_policy(user_input, data_valid=self._data_valid)
            errors |= {CONF_AVAILABILITY_POLICY: refused} if refused else {}
            kept = {k: v for k, v in values.items() if k not in (*TIMES, CONF_AVAILABILITY_POLICY)}
            part, found_errors, found = self._part_at(
                values[CONF_ROLE], address, data_type, self._taken()
            )
            errors |= found_errors
            placeholders |= found
            if part is not None and not errors:
                part = {**kept, **part, **travel, **supervision, **policy}
                rows = [
                    {k: v for k, v in row.items() if k not in TIMES}
                    for row in self._entity_rows(self._part_ids[0])
                ]
                if problems := group_errors([*rows, part]):
                    errors["base"] = problems[0][1]
                    placeholders |= problems[0][2]
                for _part, key, details in self._layout_errors([part], []):
                    errors[CONF_ADDRESS] = key
                    placeholders |= details
            if not errors and part is not None:
                self._parts = [part]
                return await self.async_step_composite_part()
        schema = vol.Schema(
            {
                vol.Required(CONF_ADDRESS): TextSelector(),
                vol.Optional(CONF_DATA_TYPE): data_types(self._client),
            }
        )
        if time := entity_time(platform):
            schema = schema.extend({vol.Optional(time): _SECONDS})
        schema = schema.extend(policy_field(data_valid=self._data_valid))
        return self.async_show_form(
            step_id="composite_edit",
            data_schema=self.add_suggested_values_to_schema(schema, user_input or values),
            errors=errors,
            description_placeholders=placeholders,
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

    def _entity_rows(self, point_id: str) -> list[dict[str, Any]]:
        """Return the other parts of the entity a part belongs to."""
        entity = entity_of(self._points[point_id])
        return [
            data
            for other, data in self._points.items()
            if other != point_id and entity_of(data) == entity
        ]


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
