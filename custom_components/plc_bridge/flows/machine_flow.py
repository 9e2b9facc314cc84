"""The device flow's machine page: its name, its area, the address that says its data is valid."""

from __future__ import annotations

from typing import Any

from homeassistant.config_entries import SubentryFlowResult
from homeassistant.const import CONF_NAME
from homeassistant.helpers.selector import AreaSelector, TextSelector
import voluptuous as vol

from ..const import CONF_AREA
from ..model.availability import availability_fields, check_availability, shown_availability
from .base import DeviceFlowBase


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
