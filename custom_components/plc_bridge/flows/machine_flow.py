"""The device flow's machine page (name, area, data-valid address), and its copies.

"Add machines like this one" (a stored machine's menu) makes copies of it (model/template.py).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from types import MappingProxyType
from typing import Any

from homeassistant.config_entries import ConfigSubentry, SubentryFlowResult
from homeassistant.const import CONF_NAME
from homeassistant.helpers.selector import (
    AreaSelector,
    NumberSelector,
    NumberSelectorConfig,
    NumberSelectorMode,
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
    TextSelector,
)
import voluptuous as vol

from ..const import CONF_AREA, CONF_POINTS, SUBENTRY_DEVICE
from ..model.availability import availability_fields, check_availability, shown_availability
from ..model.composite import assign_entities
from ..model.template import (
    CONF_COPY_OF,
    CONF_COUNT,
    CONF_NAME_PATTERN,
    CONF_PART,
    CONF_STRIDE,
    CONF_TEMPLATE,
    CONF_UNIT,
    MAX_COPIES,
    NUMBER_MARK,
    TemplateError,
    make_copies,
    new_template,
)
from ..plc import PlcClient
from ..plc.shifting import NAME
from .base import DeviceFlowBase

BOX = NumberSelectorMode.BOX


class MachineStep(DeviceFlowBase):
    """The machine page of the device flow (a base of its handler)."""

    async def async_step_device(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """Name the device (a machine or part of the plant) and suggest its area."""
        errors: dict[str, str] = {}
        detail = ""
        if user_input is not None:
            name = str(user_input.get(CONF_NAME, "")).strip()
            availability, errors, detail = check_availability(self._client, user_input)
            if not name:
                errors[CONF_NAME] = "device_name_required"
            if not errors:
                self._name, self._area = name, user_input.get(CONF_AREA) or None
                self._availability = availability
                return await self.async_step_menu()
        schema = vol.Schema(
            {
                vol.Required(CONF_NAME): TextSelector(),
                vol.Optional(CONF_AREA): AreaSelector(),
                **availability_fields(self._client),
            }
        )
        shown = {CONF_NAME: self._name, CONF_AREA: self._area}
        shown |= shown_availability(self._availability) | dict(user_input or {})
        return self.async_show_form(
            step_id="device",
            data_schema=self.add_suggested_values_to_schema(schema, shown),
            errors=errors,
            description_placeholders={"error": detail},
        )

    def _machine_data(self) -> dict[str, Any]:
        """The machine as the flow holds it, as stored: points, area, availability, its record.

        The template record (or a copy's mark) of a reconfigured machine stays as it was:
        editing the original changes the original only.
        """
        assign_entities(self._points)
        data: dict[str, Any] = {CONF_POINTS: self._points}
        if self._area:
            data[CONF_AREA] = self._area
        data |= self._availability
        if self.source == "reconfigure":
            stored = self._get_reconfigure_subentry().data
            data |= {key: stored[key] for key in (CONF_TEMPLATE, CONF_COPY_OF) if key in stored}
        return data

    def _can_copy(self) -> bool:
        """True where "Add machines like this one" is offered: a stored machine, not a copy."""
        return (
            self.source == "reconfigure"
            and bool(self._points)
            and bool(self._client.shift_units)
            and CONF_COPY_OF not in self._get_reconfigure_subentry().data
        )

    async def async_step_copies(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """Add machines like this one: how many, how their addresses move, how they are named.

        Every copy is checked before any is stored; the machine is saved with the record.
        """
        entry, subentry = self._get_entry(), self._get_reconfigure_subentry()
        stored = subentry.data.get(CONF_TEMPLATE)
        errors: dict[str, str] = {}
        placeholders = {"error": "", "copy": ""}
        if user_input is not None:
            original = self._machine_data()
            others = [
                (other.title, other.data)
                for other in entry.subentries.values()
                if other.subentry_type == SUBENTRY_DEVICE
                and other.subentry_id != subentry.subentry_id
            ]
            try:
                template = new_template(self._client, stored, user_input)
                count = int(user_input[CONF_COUNT])
                copies = make_copies(
                    self._client, template, original, count, [*others, (self._name, original)]
                )
            except TemplateError as err:
                errors[err.field] = "template_refused" if err.copy else "template_invalid"
                placeholders = {"error": str(err), "copy": str(err.copy or "")}
            else:
                for made in copies:
                    self.hass.config_entries.async_add_subentry(
                        entry,
                        ConfigSubentry(
                            data=MappingProxyType(made.data),
                            subentry_type=SUBENTRY_DEVICE,
                            title=made.title,
                            unique_id=None,
                        ),
                    )
                original[CONF_TEMPLATE] = replace(template, count=template.count + count).as_data()
                return self.async_update_and_abort(entry, subentry, title=self._name, data=original)
        return self.async_show_form(
            step_id="copies",
            data_schema=self.add_suggested_values_to_schema(
                copies_schema(self._client), user_input or self._suggested_copies(stored)
            ),
            errors=errors,
            description_placeholders={"name": self._name, **placeholders},
        )

    def _suggested_copies(self, stored: Mapping[str, Any] | None) -> dict[str, Any]:
        """What the copies form suggests: the record's way, else names after this machine's."""
        if stored:
            return {key: value for key, value in stored.items() if key != CONF_COUNT}
        stem = self._name.rstrip("0123456789").rstrip() or self._name
        return {CONF_NAME_PATTERN: f"{stem} {NUMBER_MARK}", CONF_STRIDE: 1}


def copies_schema(client: type[PlcClient]) -> vol.Schema:
    """Return the copies form: count, then the stride and its unit, or the part that counts."""
    number = NumberSelector(NumberSelectorConfig(min=1, max=MAX_COPIES, step=1, mode=BOX))
    fields: dict[vol.Marker, Any] = {vol.Required(CONF_COUNT): number}
    if NAME in client.shift_units:
        fields[vol.Required(CONF_PART)] = TextSelector()
    else:
        fields[vol.Required(CONF_UNIT, default=client.shift_units[0])] = SelectSelector(
            SelectSelectorConfig(
                options=list(client.shift_units),
                translation_key=CONF_UNIT,
                mode=SelectSelectorMode.DROPDOWN,
            )
        )
    stride = NumberSelector(NumberSelectorConfig(min=-65535, max=65535, step=1, mode=BOX))
    fields[vol.Required(CONF_STRIDE, default=1)] = stride
    fields[vol.Required(CONF_NAME_PATTERN)] = TextSelector()
    return vol.Schema(fields)
