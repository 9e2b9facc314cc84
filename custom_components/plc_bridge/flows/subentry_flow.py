"""The device subentry flow: a machine or part of the plant, and the points it holds.

Name and area first, then a menu (as MQTT's device subentries): add a point (entity type and
address, then the settings that fit them), pick points from the PLC's variables, import a
pasted table, edit or remove a point, save. Reconfigure opens the same menu.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
import secrets
from typing import Any

from homeassistant.config_entries import ConfigEntryState, SubentryFlowResult
from homeassistant.const import CONF_DEVICE_CLASS
from homeassistant.core import HomeAssistant
from homeassistant.helpers.selector import TextSelector, TextSelectorConfig
from homeassistant.helpers.translation import async_get_translations
import voluptuous as vol

from ..const import (
    CONF_ADDRESS,
    CONF_AREA,
    CONF_DATA_TYPE,
    CONF_PLATFORM,
    CONF_POINTS,
    CONF_READ_ONLY,
    CONF_ROLE,
    DOMAIN,
    SUBENTRY_DEVICE,
    SUBENTRY_EXPOSE,
)
from ..model.availability import (
    AVAILABILITY_FIELDS,
    CONF_AVAILABILITY_POLICY,
    check_policy,
    has_data_valid,
    policy_field,
)
from ..model.device_classes import device_classes
from ..model.plc_config import PlcConfig, Problem, Subentry
from ..model.point_table import async_describe, parse_points, plain
from ..model.points import check_point, point_data
from ..plc import PlcError
from .composite_flow import CompositeSteps, defaulted, layout_errors
from .flow_lists import (
    CONF_FILTER,
    CONF_VARIABLES,
    MAX_LISTED,
    async_point_words,
    async_type_names,
    filled,
    listing,
    matching,
    pick_schema,
    picked_points,
    point_choice,
)
from .machine_flow import MachineStep
from .point_form import BASE_FIELDS, base_schema, details_schema

CONF_POINT = "point"
CONF_TABLE = "table"


class DeviceSubentryFlowHandler(CompositeSteps, MachineStep):
    """Add or edit a device of the PLC and its points."""

    async def async_step_user(self, user_input: dict[str, Any] | None = None) -> SubentryFlowResult:
        """Ask the device's name and area."""
        return await self.async_step_device(user_input)

    async def async_step_reconfigure(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """Edit a device: its points, name and area are loaded into the menu."""
        subentry = self._get_reconfigure_subentry()
        self._name = subentry.title
        self._area = subentry.data.get(CONF_AREA)
        self._availability = {
            k: subentry.data[k] for k in AVAILABILITY_FIELDS if k in subentry.data
        }
        self._points = {pid: dict(data) for pid, data in subentry.data.get(CONF_POINTS, {}).items()}
        return await self.async_step_menu()

    async def async_step_point(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """A point's name, entity type, address and data type."""
        errors: dict[str, str] = {}
        placeholders: dict[str, str] = {}
        if user_input is not None:
            point, _, errors, placeholders = check_point(self._client, user_input)
            if kind := placeholders.get(CONF_DATA_TYPE):  # named as the data-type list names it
                placeholders[CONF_DATA_TYPE] = (await async_type_names(self.hass)).get(kind, kind)
            if point is not None and point in self._taken():
                errors[CONF_ADDRESS] = "already_configured"
            if point is not None and not errors:
                given = {**user_input, CONF_ADDRESS: point.address, CONF_DATA_TYPE: point.data_type}
                for _data, key, found in layout_errors(
                    self._client, self._plc_points(), [defaulted(given)]
                ):
                    errors[CONF_ADDRESS] = key
                    placeholders |= found
            if not errors:
                self._base = dict(user_input)
                return await self.async_step_details()
        else:
            user_input = self._points.get(self._editing or "", {})
        return self.async_show_form(
            step_id="point",
            data_schema=self.add_suggested_values_to_schema(base_schema(self._client), user_input),
            errors=errors,
            description_placeholders={"error": "", "point": "", "written": "", **placeholders},
        )

    async def async_step_details(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """The settings that fit the point's entity type and value."""
        point, kind, _, _ = check_point(self._client, self._base)
        platform = self._base[CONF_PLATFORM]
        errors: dict[str, str] = {}
        placeholders: dict[str, str] = {"units": "", "point": "", "written": ""}
        if user_input is not None:
            data, errors, found = point_data(self._client, {**self._base, **user_input})
            placeholders |= found
            policy, wrong = check_policy(user_input, data_valid=has_data_valid(self._availability))
            errors |= {CONF_AVAILABILITY_POLICY: wrong} if wrong else {}
            data |= policy
            for _data, key, details in (
                layout_errors(self._client, self._plc_points(), [data]) if not errors else []
            ):
                errors[CONF_READ_ONLY] = key
                placeholders |= details
            if not errors:
                self._points[self._editing or secrets.token_hex(6)] = data
                self._editing = None
                return await self.async_step_menu()
        suggested: Mapping[str, Any] = user_input or {
            **self._points.get(self._editing or "", {}),
            **{key: self._base[key] for key in BASE_FIELDS},
        }
        device_class = suggested.get(CONF_DEVICE_CLASS)
        if device_class not in device_classes(platform, kind):  # the entity type was changed
            suggested, device_class = dict(suggested, device_class=None), None
        return self.async_show_form(
            step_id="details",
            data_schema=self.add_suggested_values_to_schema(
                details_schema(platform, kind, device_class).extend(
                    policy_field(data_valid=has_data_valid(self._availability))
                ),
                suggested,
            ),
            errors=errors,
            description_placeholders={
                **placeholders,
                "address": point.address if point else "",
                "platform": platform,
            },
        )

    async def async_step_edit(self, user_input: dict[str, Any] | None = None) -> SubentryFlowResult:
        """Choose the point to edit."""
        if user_input is not None:
            if self._points[user_input[CONF_POINT]].get(CONF_ROLE):
                return await self.async_edit_part(user_input[CONF_POINT])
            self._editing = user_input[CONF_POINT]
            return await self.async_step_point()
        return self.async_show_form(
            step_id="edit",
            data_schema=vol.Schema(
                {
                    vol.Required(CONF_POINT): point_choice(
                        self._points,
                        self._client,
                        await async_point_words(self.hass),
                        multiple=False,
                    )
                }
            ),
        )

    async def async_step_remove(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """Choose the points to remove; an entity keeps a part that shows it, or goes whole."""
        chosen = list((user_input or {}).get(CONF_POINT, []))
        errors, placeholders = self.removal_errors(chosen)
        if user_input is not None and not errors:
            self._points = {k: v for k, v in self._points.items() if k not in chosen}
            return await self.async_step_menu()
        schema = vol.Schema(
            {
                vol.Optional(CONF_POINT): point_choice(
                    self._points, self._client, await async_point_words(self.hass), multiple=True
                )
            }
        )
        return self.async_show_form(
            step_id="remove",
            data_schema=self.add_suggested_values_to_schema(schema, {CONF_POINT: chosen}),
            errors=errors,
            description_placeholders={"name": "", "roles": "", **placeholders},
        )

    async def async_step_browse(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """Ask which variables to list: part of their name (a PLC publishes hundreds)."""
        entry = self._get_entry()
        if entry.state is not ConfigEntryState.LOADED:
            return await self.async_step_menu()  # unloaded since the menu was shown
        if user_input is None:
            return self.async_show_form(
                step_id="browse",
                data_schema=vol.Schema({vol.Optional(CONF_FILTER): TextSelector()}),
            )
        self._items, self._ticked = [], []
        try:
            if self._published is None:
                self._published = await entry.runtime_data.client.browse()
        except PlcError as err:
            return self._pick_form({"base": "browse_failed"}, {"error": str(err)})
        needle = str(user_input.get(CONF_FILTER, ""))
        self._items = matching(self._published, needle, self._taken())
        unlisted = [
            name for name in entry.runtime_data.client.unlisted if needle.lower() in name.lower()
        ]
        if unlisted:  # said on the form, not left out in silence
            return self._pick_form({"base": "browse_unlisted"}, {"error": ", ".join(unlisted)})
        return self._pick_form()

    def _pick_form(
        self, errors: dict[str, str] | None = None, placeholders: dict[str, str] | None = None
    ) -> SubentryFlowResult:
        """List the matching variables to tick (ticks kept); `pick_first`: the first of more."""
        return self.async_show_form(
            step_id="pick" if len(self._items) <= MAX_LISTED else "pick_first",
            data_schema=self.add_suggested_values_to_schema(
                pick_schema(self._items), {CONF_VARIABLES: self._ticked}
            ),
            errors=errors,
            description_placeholders={
                "count": str(len(self._items)),
                "shown": str(min(len(self._items), MAX_LISTED)),
                "error": "",
                **(placeholders or {}),
            },
        )

    async def async_step_pick(self, user_input: dict[str, Any] | None = None) -> SubentryFlowResult:
        """Pick any number of the listed variables; each becomes a point (none if one is bad)."""
        self._ticked = list((user_input or {}).get(CONF_VARIABLES, []))
        ticked = [self._items[int(index)] for index in self._ticked]
        points, refused = picked_points(self._client, ticked, await async_describe(self.hass))
        if refused:
            return self._pick_form({"base": "pick_failed"}, {"error": listing(refused)})
        self._points |= {secrets.token_hex(6): data for data in points}
        return await self.async_step_menu()

    async_step_pick_first = async_step_pick  # the first MAX_LISTED of a longer list

    async def async_step_import_points(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """Take pasted lines, all checked; nothing joins the device unless every line is good."""
        errors: dict[str, str] = {}
        problems: list[tuple[int, str]] = []
        if user_input is not None:
            table, assumed = str(user_input.get(CONF_TABLE, "")), list[tuple[int, str]]()
            describe, known = await async_describe(self.hass), self._points.values()
            points, problems = parse_points(
                self._client,
                table,
                self._taken(),
                describe,
                assumed=assumed,
                known=known,
                plc=self._plc_points(),
                data_valid=has_data_valid(self._availability),
            )
            if not problems and (not assumed or table == self._confirmed):
                self._points |= {secrets.token_hex(6): data for data in points}
                return await self.async_step_menu()
            errors[CONF_TABLE] = "import_failed" if problems else "import_types_assumed"
            if not problems:  # shown once: the same table submitted again is imported
                self._confirmed, problems = table, assumed
        schema = vol.Schema(
            {vol.Required(CONF_TABLE): TextSelector(TextSelectorConfig(multiline=True))}
        )
        return self.async_show_form(
            step_id="import_points",
            data_schema=self.add_suggested_values_to_schema(schema, user_input or {}),
            errors=errors,
            description_placeholders={
                "errors": listing([f"line {line}: {text}" for line, text in problems])
            },
        )

    async def async_step_save(self, user_input: dict[str, Any] | None = None) -> SubentryFlowResult:
        """Store the device and its points, unless the PLC with it has a problem it had not.

        A menu choice cannot carry an error: a refusal is a form of its own naming the
        problem, whose submission leads back to the menu.
        """
        if user_input is not None:
            return await self.async_step_menu()
        data = self._machine_data()
        if (problem := await self._new_problem(data)) is not None:
            return self.async_show_form(
                step_id="save",
                errors={"base": "save_refused"},
                description_placeholders={"problem": problem, "name": self._name},
            )
        if self.source == "reconfigure":
            return self.async_update_and_abort(
                self._get_entry(), self._get_reconfigure_subentry(), title=self._name, data=data
            )
        return self.async_create_entry(title=self._name, data=data)

    async def _new_problem(self, data: dict[str, Any]) -> str | None:
        """Return the first problem the PLC would have with the machine saved, worded; else None.

        The one validation of a stored PLC (`PlcConfig.problems`) decides; problems the PLC
        has already (stored before a rule existed) do not keep a machine from being saved.
        """
        stored = PlcConfig.from_entry(self._get_entry())
        at = self._reconfigure_subentry_id if self.source == "reconfigure" else ""
        machine = Subentry(
            at=at, subentry_type=SUBENTRY_DEVICE, title=self._name, unique_id=None, data=data
        )
        subentries = [*stored.subentries, machine]
        if at:
            subentries = [machine if sub.at == at else sub for sub in stored.subentries]
        saved = replace(stored, subentries=tuple(subentries))
        describe = await async_describe(self.hass)
        before = stored.problems(self._client, describe)
        for problem in saved.problems(self._client, describe):
            if problem not in before:
                return problem_words(problem, await _error_texts(self.hass))
        return None


ERROR_TEXTS = (
    f"component.{DOMAIN}.config_subentries.{SUBENTRY_DEVICE}.error.",
    f"component.{DOMAIN}.config_subentries.{SUBENTRY_EXPOSE}.error.",
    f"component.{DOMAIN}.options.error.",
)
"""Where the forms' errors are worded: a problem's form error is one of theirs."""


async def _error_texts(hass: HomeAssistant) -> dict[str, str]:
    """Return the forms' error texts, in Home Assistant's language."""
    texts: dict[str, str] = {}
    for category in ("config_subentries", "options"):
        texts |= await async_get_translations(hass, hass.config.language, category, [DOMAIN])
    return texts


def problem_words(problem: Problem, texts: Mapping[str, str]) -> str:
    """Return a problem worded as the form that refuses it words it, naming its point."""
    words = problem.placeholders
    point = words.get("point", "")
    if "problem" in words:
        text = words["problem"]
    else:
        key = problem.field_key
        found = next((texts[prefix + key] for prefix in ERROR_TEXTS if prefix + key in texts), None)
        given = {
            **words,
            "written": words.get("address", ""),
            "point": words.get("other") or point,
            "fast_minimum": words.get("minimum", ""),
        }
        text = plain(key, words) if found is None else filled(found, given)
    return f"{point}: {text}" if point and point not in text else text
