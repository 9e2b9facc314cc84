"""Subentry flow of PLC Bridge: one point (one entity) per subentry, browsed or typed in."""

from __future__ import annotations

from typing import Any

from homeassistant.config_entries import ConfigEntryState, ConfigSubentryFlow, SubentryFlowResult
from homeassistant.const import CONF_NAME
from homeassistant.helpers.selector import (
    SelectOptionDict,
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
)
import voluptuous as vol

from .const import CONF_ADDRESS, CONF_DATA_TYPE, CONF_VENDOR
from .plc import BrowseItem, PlcClient, PlcError
from .plc.vendors import client_class
from .point_form import browse_values, point_data, point_schema

CONF_VARIABLE = "variable"
MANUAL = "manual"


def variable_label(item: BrowseItem) -> str:
    """Return how a published variable is listed: its name, address and type."""
    name = f"{item.name} – " if item.name and item.name != item.address else ""
    return f"{name}{item.address} ({item.data_type})"


class PointSubentryFlowHandler(ConfigSubentryFlow):
    """Add or edit one point; where the PLC publishes its variables, pick one first."""

    def __init__(self) -> None:
        """Start with an empty form and nothing browsed."""
        self._suggested: dict[str, Any] = {}
        self._browsed = False
        self._items: list[BrowseItem] = []

    @property
    def _client_class(self) -> type[PlcClient]:
        """The client class of the entry's vendor: its parser, data types and platforms."""
        return client_class(self._get_entry().data[CONF_VENDOR])

    async def async_step_user(self, user_input: dict[str, Any] | None = None) -> SubentryFlowResult:
        """Add a point: browse first where the vendor can, then the point form."""
        if user_input is None and self._client_class.can_browse and not self._browsed:
            return await self.async_step_browse()
        return self._point_step("user", user_input)

    async def async_step_browse(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """List the variables the PLC publishes; the chosen one fills in the point form."""
        if user_input is not None:
            self._browsed = True
            choice = user_input[CONF_VARIABLE]
            if choice != MANUAL:
                self._suggested = browse_values(self._client_class, self._items[int(choice)])
            return self._point_step("user", None)
        entry = self._get_entry()
        if entry.state is not ConfigEntryState.LOADED:
            return self.async_abort(reason="entry_not_loaded")
        client: PlcClient = entry.runtime_data.client
        try:
            items = await client.browse()
        except PlcError as err:
            self._browsed = True
            return self._point_step("user", None, {"base": "browse_failed"}, {"error": str(err)})
        configured = {subentry.unique_id for subentry in entry.subentries.values()}
        self._items = [
            item for item in items if f"{item.address}|{item.data_type}" not in configured
        ]
        options = [SelectOptionDict(value=MANUAL, label=MANUAL)] + [
            SelectOptionDict(value=str(index), label=variable_label(item))
            for index, item in enumerate(self._items)
        ]
        return self.async_show_form(
            step_id="browse",
            data_schema=vol.Schema(
                {
                    vol.Required(CONF_VARIABLE, default=MANUAL): SelectSelector(
                        SelectSelectorConfig(
                            options=options,
                            translation_key=CONF_VARIABLE,
                            mode=SelectSelectorMode.DROPDOWN,
                        )
                    )
                }
            ),
            description_placeholders={"count": str(len(self._items))},
        )

    async def async_step_reconfigure(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """Edit a point; the same checks as when it was added."""
        if user_input is None:
            subentry = self._get_reconfigure_subentry()
            self._suggested = {**subentry.data, CONF_NAME: subentry.title}
        return self._point_step("reconfigure", user_input)

    def _point_step(
        self,
        step_id: str,
        user_input: dict[str, Any] | None,
        errors: dict[str, str] | None = None,
        placeholders: dict[str, str] | None = None,
    ) -> SubentryFlowResult:
        """Check a submitted point form and save it, or show the form (again)."""
        client = self._client_class
        if user_input is not None:
            data, errors, placeholders = point_data(client, user_input)
            if not errors:
                return self._save(step_id, user_input[CONF_NAME], data)
        return self.async_show_form(
            step_id=step_id,
            data_schema=self.add_suggested_values_to_schema(
                point_schema(client), user_input or self._suggested
            ),
            errors=errors,
            description_placeholders=placeholders,
        )

    def _save(self, step_id: str, title: str, data: dict[str, Any]) -> SubentryFlowResult:
        """Create or update the subentry; abort when another point has the same address."""
        entry = self._get_entry()
        unique_id = f"{data[CONF_ADDRESS]}|{data[CONF_DATA_TYPE]}"
        editing = self._get_reconfigure_subentry() if step_id == "reconfigure" else None
        for subentry_id, subentry in entry.subentries.items():
            if subentry.unique_id == unique_id and (
                editing is None or subentry_id != editing.subentry_id
            ):
                return self.async_abort(reason="already_configured")
        if editing is None:
            return self.async_create_entry(title=title, data=data, unique_id=unique_id)
        return self.async_update_and_abort(
            entry, editing, title=title, data=data, unique_id=unique_id
        )
