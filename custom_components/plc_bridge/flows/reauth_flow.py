"""Reauth steps of the config flow: the credentials, or the vendor fields that authenticate."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from homeassistant.config_entries import ConfigFlowResult
from homeassistant.const import CONF_USERNAME
import voluptuous as vol

from ..const import CONF_OPTIONS, CONF_VENDOR
from ..model.plc_config import Connection, file_problems
from ..model.vendor_fields import VENDOR_FIELDS
from ..plc.vendors import client_class
from .base import PlcFlowBase
from .connection_form import CREDENTIALS_SCHEMA, fields_schema, on_form
from .vendor_steps import Input


class ReauthSteps(PlcFlowBase):
    """Ask again for what the PLC refused, check it as a new PLC is checked, then store it."""

    async def async_step_reauth(self, entry_data: Mapping[str, Any]) -> ConfigFlowResult:
        """Start re-authentication after the PLC refused the stored credentials."""
        if client_class(entry_data[CONF_VENDOR]).credential_option is not None:
            return await self._reauth_options(None)
        return await self.async_step_reauth_confirm()

    async def _reauth_options(self, user_input: Input = None) -> ConfigFlowResult:
        """Ask again for the vendor fields that authenticate (not a user); check, then store."""
        entry = self._get_reauth_entry()
        vendor = entry.data[CONF_VENDOR]
        fields = [field for field in VENDOR_FIELDS[vendor] if field.credential]
        schema = vol.Schema(fields_schema(fields))
        errors: dict[str, str] = {}
        if user_input is not None:
            stored = entry.data.get(CONF_OPTIONS, {})
            folder = self.hass.config.config_dir
            submitted, problems = await self.hass.async_add_executor_job(
                file_problems, vendor, folder, user_input, stored
            )
            data = {**entry.data, CONF_OPTIONS: {**stored, **submitted}}
            problems = problems or list(Connection.from_data(data).problems())
            if problems:  # the model's checks, as the connection pages and the pasted file
                errors = self._errors_of(problems)
            else:
                data[CONF_OPTIONS] = client_class(vendor).validate_options(data[CONF_OPTIONS])
                device, errors = await self._connect(data)
                if device is not None:
                    return self._store(entry, "reauth_successful", data)
        return self.async_show_form(
            step_id=f"reauth_{vendor}",
            data_schema=schema,
            errors=on_form(errors, schema),
            description_placeholders={"name": entry.title, "problem": self._problem},
        )

    async def async_step_reauth_confirm(self, user_input: Input = None) -> ConfigFlowResult:
        """Ask for the credentials again and check them before storing."""
        entry = self._get_reauth_entry()
        errors: dict[str, str] = {}
        if user_input is not None:
            data = {**entry.data, **user_input}
            device, errors = await self._connect(data)
            if device is not None:
                return self._store(entry, "reauth_successful", data)
        return self.async_show_form(
            step_id="reauth_confirm",
            data_schema=self.add_suggested_values_to_schema(
                CREDENTIALS_SCHEMA, {CONF_USERNAME: entry.data.get(CONF_USERNAME)}
            ),
            errors=on_form(errors, CREDENTIALS_SCHEMA),
            description_placeholders={"name": entry.title, "problem": self._problem},
        )
