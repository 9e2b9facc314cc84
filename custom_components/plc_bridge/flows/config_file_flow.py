"""The config flow's way to add a PLC from a file the `export_config` action wrote.

The pasted text is checked before anything else, off the event loop: plain YAML only, keys the
model knows, values of their kind, every point's address with the vendor's parser, the forms'
rules, the poll intervals' floors, every expose through the expose's one validation and files
inside the configuration folder; each refusal names its line. Then the normal connection page,
filled in from the file (host, port, and the certificate page where TLS is pinned: a pasted
fingerprint is never trusted), takes the secrets; a last page lists what each expose would
write, and every expose starts with sending off: nothing is written while the file is applied.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from homeassistant.config_entries import ConfigFlowResult, ConfigSubentryData
from homeassistant.helpers import area_registry as ar
from homeassistant.helpers.selector import TextSelector, TextSelectorConfig
import voluptuous as vol

from ..const import CONF_AREA, CONF_FINGERPRINT, CONF_OPTIONS, SUBENTRY_EXPOSE
from ..model.config_file import (
    ConfigFile,
    ConfigFileError,
    check_pasted,
    load_config,
)
from ..model.expose import expose_config
from ..model.plc_config import file_problems
from ..model.point_table import async_describe
from ..model.yaml_text import YamlTextError, check_size
from ..plc import PlcError
from ..plc.vendors import client_class
from .base import PlcFlowBase

PASTE = "paste_configuration"
"""The first page's menu choice (beside connecting to a PLC) and the step taking the file."""
CONF_CONFIGURATION = "configuration"
PASTE_SCHEMA = vol.Schema(
    {vol.Required(CONF_CONFIGURATION): TextSelector(TextSelectorConfig(multiline=True))}
)
PLACEHOLDERS = (
    *("line", "problem", "vendor", "point", "address", "other", "name", "kind"),
    *("limit", "depth", "tag", "value", "minimum", "error", "pair"),
)
"""What the pasted file's errors name; each form passes them all (empty where unused)."""


class ConfigFileSteps(PlcFlowBase):
    """The steps that add a PLC from a pasted file; the config flow proper inherits them."""

    _pasted: ConfigFile | None = None

    async def async_step_paste_configuration(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Take the pasted file; refuse it on its field (and line) when it cannot become a PLC.

        Then the connection page, filled in from the file: its host and port (and, pinned, the
        certificate the PLC presents) are shown and checked before any secret is sent.
        """
        errors: dict[str, str] = {}
        placeholders = dict.fromkeys(PLACEHOLDERS, "")
        if user_input is not None:
            try:
                pasted = await self._pasted_file(user_input[CONF_CONFIGURATION])
            except ConfigFileError as err:
                errors[CONF_CONFIGURATION] = err.key
                placeholders |= err.placeholders
            else:
                self._pasted = pasted
                self._vendor = pasted.vendor
                self._data = {**pasted.data, CONF_OPTIONS: dict(pasted.data[CONF_OPTIONS])}
                self._data.pop(CONF_FINGERPRINT, None)  # trusted only once the user has seen it
                return self._connection_form({})
        return self.async_show_form(
            step_id=PASTE,
            data_schema=self.add_suggested_values_to_schema(PASTE_SCHEMA, user_input or {}),
            errors=errors,
            description_placeholders=placeholders,
        )

    async def _pasted_file(self, text: str) -> ConfigFile:
        """Return the pasted file read (off the event loop) and checked as every form checks."""
        try:
            check_size(text)
        except YamlTextError as err:
            raise ConfigFileError(err.key, **err.placeholders) from err
        pasted = await self.hass.async_add_executor_job(load_config, text, self.VERSION)
        options = pasted.data[CONF_OPTIONS]
        files, problems = await self.hass.async_add_executor_job(
            file_problems, pasted.vendor, self.hass.config.config_dir, options, {}
        )
        for problem in problems[:1]:
            line = pasted.line(problem.path)
            raise ConfigFileError(problem.key, line=line, **problem.placeholders)
        pasted = replace(pasted, data={**pasted.data, CONF_OPTIONS: options | files})
        client = client_class(pasted.vendor, pasted.data[CONF_OPTIONS])
        subentries = check_pasted(client, pasted, await async_describe(self.hass))
        return replace(pasted, subentries=subentries)

    async def async_step_paste_exposes(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """List what each pasted expose would write; all start with sending off."""
        assert self._pasted is not None
        if user_input is not None:
            return self._create_pasted(self._pasted)
        return self._exposes_form(self._pasted)

    def _exposes_form(self, pasted: ConfigFile) -> ConfigFlowResult:
        """Show each pasted expose: its entity, its address, the value it would write now."""
        client = client_class(self._vendor)
        lines = []
        for subentry in pasted.subentries:
            if subentry["subentry_type"] != SUBENTRY_EXPOSE:
                continue
            expose = expose_config("", subentry["title"], subentry["data"])
            source = expose.source(self.hass.states.get(expose.entity_id))
            try:
                value = "—" if source is None else repr(expose.plc_value(client, source))
            except PlcError:
                value = "—"
            lines.append(f"- {expose.entity_id} → {expose.point.address}: {value}")
        return self.async_show_form(
            step_id="paste_exposes",
            description_placeholders={"exposes": "\n".join(lines)},
        )

    def _create_entry(self, title: str) -> ConfigFlowResult:
        """Create the entry: named as the PLC reports, or as the pasted file with its contents.

        A pasted file with exposes shows first what each would write (none writes yet).
        """
        pasted = self._pasted
        if pasted is None:
            return super()._create_entry(title)
        if any(sub["subentry_type"] == SUBENTRY_EXPOSE for sub in pasted.subentries):
            return self._exposes_form(pasted)
        return self._create_pasted(pasted)

    def _create_pasted(self, pasted: ConfigFile) -> ConfigFlowResult:
        """Create the entry of the pasted file with its machines, exposes and options.

        A file of an older entry version makes an entry of that version: Home Assistant then
        migrates it as it migrates a stored one, before it is set up.
        """
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
