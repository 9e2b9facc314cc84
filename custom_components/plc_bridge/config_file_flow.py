"""The config flow's way to add a PLC from a file the `export_config` action wrote.

The pasted text is checked before anything else (format, vendor, every point's address with
the vendor's parser); only the secrets the file left out are asked for; then the normal flow's
checks connect, and the entry is created with the file's devices, exposes and options.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from homeassistant.config_entries import ConfigFlow, ConfigFlowResult, ConfigSubentryData
from homeassistant.const import CONF_PASSWORD
from homeassistant.helpers import area_registry as ar
from homeassistant.helpers.selector import TextSelector, TextSelectorConfig
import voluptuous as vol

from .config_file import ConfigFile, ConfigFileError, check_addresses, load_config
from .connection_form import CREDENTIALS_SCHEMA, VENDOR_FIELDS, on_form, option_error
from .const import CONF_AREA, CONF_FINGERPRINT, CONF_OPTIONS
from .plc import PlcOptionError
from .plc.vendors import client_class

PASTE = "paste_configuration"
"""The first page's choice (beside the vendors) and the step taking the pasted file."""
CONF_CONFIGURATION = "configuration"
PASTE_SCHEMA = vol.Schema(
    {vol.Required(CONF_CONFIGURATION): TextSelector(TextSelectorConfig(multiline=True))}
)
PLACEHOLDERS = ("line", "problem", "vendor", "point", "address")
"""What the pasted file's errors name; each form passes them all (empty where unused)."""


class ConfigFileSteps(ConfigFlow):
    """The steps that add a PLC from a pasted file; the config flow proper inherits them."""

    _vendor: str
    _data: dict[str, Any]
    _trusted: set[str]
    _problem: str
    _pasted: ConfigFile | None = None

    async def async_step_paste_configuration(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Take the pasted file; refuse it on its field when it cannot become a PLC."""
        errors: dict[str, str] = {}
        placeholders = dict.fromkeys(PLACEHOLDERS, "")
        if user_input is not None:
            try:
                pasted = load_config(user_input[CONF_CONFIGURATION], self.VERSION)
                check_addresses(client_class(pasted.vendor), pasted)
            except ConfigFileError as err:
                errors[CONF_CONFIGURATION] = err.key
                placeholders |= err.placeholders
            else:
                self._pasted = pasted
                self._vendor = pasted.vendor
                self._data = {**pasted.data, CONF_OPTIONS: dict(pasted.data[CONF_OPTIONS])}
                if pin := pasted.data.get(CONF_FINGERPRINT):
                    # Trusted where the file was made: the same certificate is not asked again.
                    self._trusted.add(str(pin))
                return await self.async_step_paste_secrets()
        return self.async_show_form(
            step_id=PASTE,
            data_schema=self.add_suggested_values_to_schema(PASTE_SCHEMA, user_input or {}),
            errors=errors,
            description_placeholders=placeholders,
        )

    async def async_step_paste_secrets(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Ask for the secrets the file left out (none: connect at once), then connect."""
        assert self._pasted is not None
        schema = self._secrets_schema(self._pasted)
        errors: dict[str, str] = {}
        if not schema.schema:
            return await self._check_and_connect()
        if user_input is not None:
            options = {key: value for key, value in user_input.items() if key != CONF_PASSWORD}
            try:
                files = await self._resolved(self._vendor, options, {})
            except PlcOptionError as err:
                self._problem, errors = str(err), option_error(err)
            else:
                if CONF_PASSWORD in user_input:
                    self._data[CONF_PASSWORD] = user_input[CONF_PASSWORD]
                self._data[CONF_OPTIONS] |= options | files
                return await self._check_and_connect()
        return self.async_show_form(
            step_id="paste_secrets",
            data_schema=schema,
            errors=on_form(errors, schema),
            description_placeholders={"title": self._pasted.title, "problem": self._problem},
        )

    def _secrets_schema(self, pasted: ConfigFile) -> vol.Schema:
        """Return the fields of the secrets the file left out: the password, the key material."""
        fields: dict[vol.Marker, Any] = {}
        if CONF_PASSWORD in pasted.secrets:
            fields[vol.Required(CONF_PASSWORD)] = CREDENTIALS_SCHEMA.schema[CONF_PASSWORD]
        for field in VENDOR_FIELDS.get(pasted.vendor, ()):
            if field.credential and field.key in pasted.secrets:
                fields[vol.Required(field.key)] = field.selector
        return vol.Schema(fields)

    def _create_entry(self, title: str) -> ConfigFlowResult:
        """Create the entry: named as the PLC reports, or as the pasted file with its contents.

        A file of an older entry version makes an entry of that version: Home Assistant then
        migrates it as it migrates a stored one, before it is set up.
        """
        pasted = self._pasted
        if pasted is None:
            return self.async_create_entry(title=title, data=self._data)
        result = self.async_create_entry(
            title=pasted.title,
            data=self._data,
            options=pasted.options,
            subentries=[self._local_areas(subentry) for subentry in pasted.subentries],
        )
        result["version"] = pasted.version
        result["minor_version"] = pasted.minor_version
        return result

    def _local_areas(self, subentry: ConfigSubentryData) -> ConfigSubentryData:
        """Return a subentry without an area this installation lacks (area ids are local)."""
        area = subentry["data"].get(CONF_AREA)
        if area is None or ar.async_get(self.hass).async_get_area(str(area)) is not None:
            return subentry
        data = {key: value for key, value in subentry["data"].items() if key != CONF_AREA}
        return ConfigSubentryData(
            data=data,
            subentry_type=subentry["subentry_type"],
            title=subentry["title"],
            unique_id=subentry["unique_id"],
        )

    async def _check_and_connect(self) -> ConfigFlowResult:
        """Check the options, then connect and create the entry (the config flow's own)."""
        raise NotImplementedError

    async def _resolved(
        self, vendor: str, user_input: Mapping[str, Any], stored: Mapping[str, Any]
    ) -> dict[str, str]:
        """Return the submitted options that name files, resolved (the config flow's own)."""
        raise NotImplementedError
