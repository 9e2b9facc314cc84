"""The device subentry flow: a machine or part of the plant, and the points it holds.

Name and area first, then a menu (as MQTT's device subentries): add a point (entity type and
address, then the settings that fit them), pick points from the PLC's variables, import a
pasted table, edit or remove a point, save. Reconfigure opens the same menu.
"""

from __future__ import annotations

import secrets
from typing import Any

from homeassistant.config_entries import ConfigEntryState, ConfigSubentryFlow, SubentryFlowResult
from homeassistant.const import CONF_NAME
from homeassistant.helpers.selector import (
    AreaSelector,
    SelectOptionDict,
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
    TextSelector,
    TextSelectorConfig,
)
import voluptuous as vol

from .const import CONF_ADDRESS, CONF_AREA, CONF_DATA_TYPE, CONF_POINTS, CONF_VENDOR
from .plc import BrowseItem, PlcClient, PlcError, Point
from .plc.vendors import client_class
from .point_form import (
    BASE_FIELDS,
    base_schema,
    browse_values,
    check_point,
    details_schema,
    point_data,
)
from .point_table import parse_points

CONF_POINT = "point"
CONF_FILTER = "filter"
CONF_VARIABLES = "variables"
CONF_TABLE = "table"
MAX_LISTED = 200
"""Variables listed at most in one pick list: a real PLC publishes hundreds; filter first."""
MAX_ERRORS = 20
"""Import errors shown at most (the count says how many there are)."""


def variable_label(item: BrowseItem) -> str:
    """Return how a published variable is listed: its name, address and type."""
    name = f"{item.name} – " if item.name and item.name != item.address else ""
    return f"{name}{item.address} ({item.data_type})"


def _key(data: dict[str, Any]) -> Point:
    """Return the (address, data type) that makes a point unique within a PLC."""
    return Point(data[CONF_ADDRESS], data[CONF_DATA_TYPE])


class DeviceSubentryFlowHandler(ConfigSubentryFlow):
    """Add or edit a device of the PLC and its points."""

    def __init__(self) -> None:
        """Start with an unnamed device and no points."""
        self._name = ""
        self._area: str | None = None
        self._points: dict[str, dict[str, Any]] = {}
        self._editing: str | None = None
        self._base: dict[str, Any] = {}
        self._items: list[BrowseItem] = []

    @property
    def _client(self) -> type[PlcClient]:
        """The client class of the entry's vendor: its parser, data types and browsing."""
        return client_class(self._get_entry().data[CONF_VENDOR])

    def _taken(self) -> set[Point]:
        """Points of the PLC already used, outside the one being edited."""
        subentry_id = self._reconfigure_id()
        taken = {
            _key(data)
            for subentry in self._get_entry().subentries.values()
            if subentry.subentry_id != subentry_id
            for data in subentry.data.get(CONF_POINTS, {}).values()
        }
        taken |= {_key(data) for pid, data in self._points.items() if pid != self._editing}
        return taken

    def _reconfigure_id(self) -> str | None:
        """The id of the subentry being reconfigured, if this is a reconfigure."""
        return self._reconfigure_subentry_id if self.source == "reconfigure" else None

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
        self._points = {pid: dict(data) for pid, data in subentry.data.get(CONF_POINTS, {}).items()}
        return await self.async_step_menu()

    async def async_step_device(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """Name the device (a machine or part of the plant) and suggest its area."""
        if user_input is not None and str(user_input.get(CONF_NAME, "")).strip():
            self._name = str(user_input[CONF_NAME]).strip()
            self._area = user_input.get(CONF_AREA)
            return await self.async_step_menu()
        schema = vol.Schema(
            {vol.Required(CONF_NAME): TextSelector(), vol.Optional(CONF_AREA): AreaSelector()}
        )
        return self.async_show_form(
            step_id="device",
            data_schema=self.add_suggested_values_to_schema(
                schema, {CONF_NAME: self._name, CONF_AREA: self._area}
            ),
        )

    async def async_step_menu(self, user_input: dict[str, Any] | None = None) -> SubentryFlowResult:
        """Show what can be done next, and the points so far."""
        options = ["point"]
        if self._client.can_browse:
            options.append("browse")
        options.append("import_points")
        if self._points:
            options += ["edit", "remove"]
        options += ["device", "save"]
        listed = "\n".join(
            f"- {data[CONF_NAME]}: {data[CONF_ADDRESS]} ({data[CONF_DATA_TYPE]})"
            for data in self._points.values()
        )
        return self.async_show_menu(
            step_id="menu",
            menu_options=options,
            description_placeholders={
                "name": self._name,
                "count": str(len(self._points)),
                "points": listed or "-",
            },
        )

    async def async_step_point(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """A point's name, entity type, address and data type."""
        errors: dict[str, str] = {}
        placeholders: dict[str, str] = {}
        if user_input is not None:
            point, _, errors, placeholders = check_point(self._client, user_input)
            if point is not None and point in self._taken():
                errors[CONF_ADDRESS] = "already_configured"
            if not errors:
                self._base = dict(user_input)
                return await self.async_step_details()
        else:
            user_input = self._points.get(self._editing or "", {})
        return self.async_show_form(
            step_id="point",
            data_schema=self.add_suggested_values_to_schema(base_schema(self._client), user_input),
            errors=errors,
            description_placeholders=placeholders or {"error": ""},
        )

    async def async_step_details(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """The settings that fit the point's entity type and value."""
        point, kind, _, _ = check_point(self._client, self._base)
        platform = self._base["platform"]
        errors: dict[str, str] = {}
        placeholders: dict[str, str] = {"device_class": ""}
        if user_input is not None:
            data, errors, found = point_data(self._client, {**self._base, **user_input})
            placeholders |= found
            if not errors:
                self._points[self._editing or secrets.token_hex(6)] = data
                self._editing = None
                return await self.async_step_menu()
        suggested = user_input or {
            **self._points.get(self._editing or "", {}),
            **{key: self._base[key] for key in BASE_FIELDS},
        }
        return self.async_show_form(
            step_id="details",
            data_schema=self.add_suggested_values_to_schema(
                details_schema(platform, kind), suggested
            ),
            errors=errors,
            description_placeholders={
                **placeholders,
                "address": point.address if point else "",
                "platform": platform,
            },
        )

    def _point_choice(self, *, multiple: bool) -> SelectSelector:
        """A list of the device's points."""
        return SelectSelector(
            SelectSelectorConfig(
                options=[
                    SelectOptionDict(value=pid, label=f"{data[CONF_NAME]} ({data[CONF_ADDRESS]})")
                    for pid, data in self._points.items()
                ],
                multiple=multiple,
                mode=SelectSelectorMode.DROPDOWN,
            )
        )

    async def async_step_edit(self, user_input: dict[str, Any] | None = None) -> SubentryFlowResult:
        """Choose the point to edit."""
        if user_input is not None:
            self._editing = user_input[CONF_POINT]
            return await self.async_step_point()
        return self.async_show_form(
            step_id="edit",
            data_schema=vol.Schema({vol.Required(CONF_POINT): self._point_choice(multiple=False)}),
        )

    async def async_step_remove(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """Choose the points to remove."""
        if user_input is not None:
            for point_id in user_input.get(CONF_POINT, []):
                self._points.pop(point_id, None)
            return await self.async_step_menu()
        return self.async_show_form(
            step_id="remove",
            data_schema=vol.Schema({vol.Optional(CONF_POINT): self._point_choice(multiple=True)}),
        )

    async def async_step_browse(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """Ask which variables to list: part of their name (a PLC publishes hundreds)."""
        entry = self._get_entry()
        if entry.state is not ConfigEntryState.LOADED:
            return self.async_abort(reason="entry_not_loaded")
        if user_input is None:
            return self.async_show_form(
                step_id="browse",
                data_schema=vol.Schema({vol.Optional(CONF_FILTER): TextSelector()}),
                description_placeholders={"error": ""},
            )
        try:
            items = await entry.runtime_data.client.browse()
        except PlcError as err:
            return self.async_show_form(
                step_id="browse",
                data_schema=vol.Schema({vol.Optional(CONF_FILTER): TextSelector()}),
                errors={"base": "browse_failed"},
                description_placeholders={"error": str(err)},
            )
        needle = str(user_input.get(CONF_FILTER, "")).strip().lower()
        taken = self._taken()
        self._items = [
            item
            for item in items
            if Point(item.address, item.data_type) not in taken
            and (needle in item.address.lower() or needle in (item.name or "").lower())
        ]
        return await self.async_step_pick()

    async def async_step_pick(self, user_input: dict[str, Any] | None = None) -> SubentryFlowResult:
        """Pick any number of the listed variables; each becomes a point."""
        if user_input is not None:
            for index in user_input.get(CONF_VARIABLES, []):
                values = browse_values(self._client, self._items[int(index)])
                data, errors, _ = point_data(self._client, values)
                if not errors and _key(data) not in self._taken():
                    self._points[secrets.token_hex(6)] = data
            return await self.async_step_menu()
        shown = self._items[:MAX_LISTED]
        options = [
            SelectOptionDict(value=str(index), label=variable_label(item))
            for index, item in enumerate(shown)
        ]
        return self.async_show_form(
            step_id="pick",
            data_schema=vol.Schema(
                {
                    vol.Optional(CONF_VARIABLES): SelectSelector(
                        SelectSelectorConfig(
                            options=options, multiple=True, mode=SelectSelectorMode.LIST
                        )
                    )
                }
            ),
            description_placeholders={"count": str(len(self._items)), "shown": str(len(shown))},
        )

    async def async_step_import_points(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """Take pasted lines, all checked; nothing joins the device unless every line is good."""
        errors: dict[str, str] = {}
        listed = ""
        if user_input is not None:
            points, problems = parse_points(
                self._client, str(user_input.get(CONF_TABLE, "")), self._taken()
            )
            if not problems:
                self._points |= {secrets.token_hex(6): data for data in points}
                return await self.async_step_menu()
            errors[CONF_TABLE] = "import_failed"
            listed = "\n".join(f"- line {line}: {text}" for line, text in problems[:MAX_ERRORS])
            if len(problems) > MAX_ERRORS:
                listed += f"\n- … {len(problems) - MAX_ERRORS} more"
        schema = vol.Schema(
            {vol.Required(CONF_TABLE): TextSelector(TextSelectorConfig(multiline=True))}
        )
        return self.async_show_form(
            step_id="import_points",
            data_schema=self.add_suggested_values_to_schema(schema, user_input or {}),
            errors=errors,
            description_placeholders={"errors": listed},
        )

    async def async_step_save(self, user_input: dict[str, Any] | None = None) -> SubentryFlowResult:
        """Store the device and its points."""
        data: dict[str, Any] = {CONF_POINTS: self._points}
        if self._area:
            data[CONF_AREA] = self._area
        if self.source == "reconfigure":
            return self.async_update_and_abort(
                self._get_entry(), self._get_reconfigure_subentry(), title=self._name, data=data
            )
        return self.async_create_entry(title=self._name, data=data)
