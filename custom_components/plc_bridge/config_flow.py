"""Config flow of PLC Bridge: vendor, connection and certificate; reauth and reconfigure."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from homeassistant.config_entries import (
    SOURCE_RECONFIGURE,
    ConfigEntry,
    ConfigEntryState,
    ConfigFlowResult,
    ConfigSubentryFlow,
)
from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_PORT, CONF_USERNAME
from homeassistant.core import callback
from homeassistant.helpers.device_registry import format_mac
import voluptuous as vol

from .const import (
    CONF_FINGERPRINT,
    CONF_OPTIONS,
    CONF_TLS,
    CONF_VENDOR,
    DOMAIN,
    LOGGER,
    SUBENTRY_DEVICE,
    SUBENTRY_EXPOSE,
)
from .flows.config_file_flow import PASTE, ConfigFileSteps
from .flows.connection_form import (
    connection_data,
    connection_schema,
    connection_step,
    error_for,
    fields_schema,
    form_values,
    on_form,
    option_error,
    refused_field,
    second_page,
    vendor_options,
    vendor_schema,
)
from .flows.discovery import DiscoveryFlow
from .flows.expose_flow import ExposeSubentryFlowHandler
from .flows.options_flow import PlcBridgeOptionsFlow
from .flows.reauth_flow import ReauthSteps
from .flows.subentry_flow import DeviceSubentryFlowHandler
from .flows.vendor_steps import Input, with_vendor_steps
from .model.vendor_fields import SECOND_PAGES, VENDOR_FIELDS
from .plc import DeviceInfo, PlcError, PlcOptionError, PlcValueError, TlsMode
from .plc.http import fetch_fingerprint, format_fingerprint
from .plc.vendors import client_class
from .runtime.connection import create_client

CERTIFICATE_TIMEOUT = 10.0
"""Seconds to wait for the PLC's TLS handshake when fetching its certificate."""


def device_unique_id(device: DeviceInfo, data: Mapping[str, Any]) -> str:
    """Return the entry's unique id: the serial or MAC, else host:port for devices without."""
    if device.serial:
        return device.serial
    if device.mac:
        return format_mac(device.mac)
    return f"{data[CONF_HOST]}:{data[CONF_PORT]}"


@with_vendor_steps
class PlcBridgeConfigFlow(ConfigFileSteps, DiscoveryFlow, ReauthSteps, domain=DOMAIN):
    """Add a PLC: vendor (or a DHCP discovery, or a pasted file), connection, certificate.

    Each vendor's connection pages have step ids of their own, worded for its PLC family in
    strings.json; `with_vendor_steps` binds them to the shared steps below (the same checks).
    """

    VERSION = 2
    MINOR_VERSION = 2  # 2.2: TecoApi and PLCnext times are durations (migration.py)

    def __init__(self) -> None:
        """Start with nothing chosen and no certificate trusted."""
        self._vendor = ""
        self._data: dict[str, Any] = {}
        self._entered: dict[str, Any] = {}  # every value the pages took, suggested again
        self._trusted: set[str] = set()
        self._problem = ""  # the protocol layer's words for the last failure, shown in errors

    @staticmethod
    @callback
    def async_get_options_flow(config_entry: ConfigEntry) -> PlcBridgeOptionsFlow:
        """Return the options flow (poll interval)."""
        return PlcBridgeOptionsFlow()

    @classmethod
    @callback
    def async_get_supported_subentry_types(
        cls, config_entry: ConfigEntry
    ) -> dict[str, type[ConfigSubentryFlow]]:
        """Return the subentry flows: a device of the plant, holding its points; an expose."""
        return {
            SUBENTRY_DEVICE: DeviceSubentryFlowHandler,
            SUBENTRY_EXPOSE: ExposeSubentryFlowHandler,
        }

    async def async_step_user(self, user_input: Input = None) -> ConfigFlowResult:
        """Pick the vendor among those PLC Bridge implements, or paste an exported file."""
        if user_input is not None and user_input[CONF_VENDOR] == PASTE:
            return await self.async_step_paste_configuration()
        if user_input is not None:
            self._vendor = user_input[CONF_VENDOR]
            self._data = {CONF_VENDOR: self._vendor, CONF_USERNAME: "", CONF_PASSWORD: ""}
            return self._connection_form({})
        return self.async_show_form(step_id="user", data_schema=vendor_schema(PASTE))

    async def async_step_reconfigure(self, user_input: Input = None) -> ConfigFlowResult:
        """Show a configured PLC's connection page, filled in; its name stays as it is."""
        entry = self._get_reconfigure_entry()
        self._vendor = entry.data[CONF_VENDOR]
        self._data = dict(entry.data)
        self._entered = form_values(entry.data)
        self._trusted.add(entry.data.get(CONF_FINGERPRINT, ""))
        return self._connection_form({})

    async def async_step_certificate(self, user_input: Input = None) -> ConfigFlowResult:
        """Show the certificate the PLC presents now; trusting it pins it."""
        fingerprint: str = self._data[CONF_FINGERPRINT]
        if user_input is not None:
            self._trusted.add(fingerprint)
            return await self._finish()
        return self.async_show_form(
            step_id="certificate",
            description_placeholders={
                CONF_HOST: self._data[CONF_HOST],
                CONF_PORT: str(self._data[CONF_PORT]),
                CONF_FINGERPRINT: format_fingerprint(fingerprint),
            },
        )

    async def _resolved(
        self, vendor: str, user_input: Mapping[str, Any], stored: Mapping[str, Any]
    ) -> dict[str, str]:
        """Return the submitted options that name files, resolved in the config folder."""
        return await self.hass.async_add_executor_job(
            client_class(vendor).resolve_options,
            self.hass.config.config_dir,
            user_input,
            stored,
        )

    async def _connection_step(self, user_input: Input = None) -> ConfigFlowResult:
        """Take a vendor's connection page; go on to its second page, if it has one.

        Options that name files (SoftPLC's client certificate and key) are resolved in the
        config folder first; one that cannot be used is refused on its field.
        """
        if user_input is None:
            return self._connection_form({})
        self._enter(self._connection_schema(), user_input)
        try:
            files = await self._resolved(self._vendor, user_input, self._data.get(CONF_OPTIONS, {}))
        except PlcOptionError as err:
            self._problem = str(err)
            return self._connection_form(option_error(err))
        user_input = {**user_input, **files}
        client = client_class(self._vendor)
        stored = self._data.get(CONF_OPTIONS)
        self._data.update(connection_data(client, self._vendor, user_input, stored))
        if self._vendor in SECOND_PAGES:
            return self._second_form({})
        return await self._check_and_connect()

    async def _second_page_step(self, user_input: Input = None) -> ConfigFlowResult:
        """Take the fields of the way chosen on the connection page, then connect."""
        if user_input is None:
            return self._second_form({})
        fields = second_page(self._vendor, self._data[CONF_OPTIONS])[1]
        self._enter(vol.Schema(fields_schema(fields)), user_input)
        self._data[CONF_OPTIONS] |= vendor_options(fields, user_input)
        return await self._check_and_connect()

    def _enter(self, schema: vol.Schema, user_input: Mapping[str, Any]) -> None:
        """Remember a page's values but secrets; a field left empty (not sent) forgets the older."""
        for marker in schema.schema:
            self._entered.pop(str(marker), None)
        secrets = {field.key for field in VENDOR_FIELDS.get(self._vendor, ()) if field.credential}
        self._entered.update({k: v for k, v in user_input.items() if k not in secrets})

    async def _check_and_connect(self) -> ConfigFlowResult:
        """Check the vendor options, fetch the certificate in pin mode, then connect."""
        client = client_class(self._vendor)
        try:
            self._data[CONF_OPTIONS] = client.validate_options(self._data[CONF_OPTIONS])
        except PlcValueError as err:
            self._problem = str(err)
            field = err.option if isinstance(err, PlcOptionError) else "base"
            if self._vendor in SECOND_PAGES and (field == "base" or field in self._second_fields()):
                return self._second_form({field: "invalid_options"})
            return self._connection_form({field: "invalid_options"})
        self._data[CONF_FINGERPRINT] = ""
        if self._data[CONF_TLS] == TlsMode.PIN:
            try:
                self._data[CONF_FINGERPRINT] = await fetch_fingerprint(
                    self._data[CONF_HOST], self._data[CONF_PORT], CERTIFICATE_TIMEOUT
                )
            except PlcError as err:
                self._problem = str(err)
                return self._connection_form(error_for(err))
            if self._data[CONF_FINGERPRINT] not in self._trusted:
                return await self.async_step_certificate()
        return await self._finish()

    async def _finish(self) -> ConfigFlowResult:
        """Connect with the gathered settings, then create or update the entry."""
        device, errors = await self._connect(self._data)
        if device is None and (field := refused_field(self._vendor, self._data, errors)):
            return self._second_form({field: "session_refused"})
        if device is None:
            return self._connection_form(errors)
        await self.async_set_unique_id(
            device_unique_id(device, self._data), raise_on_progress=False
        )
        if self.source != SOURCE_RECONFIGURE:
            self._abort_if_unique_id_configured()
            # Named after what the PLC reports: Home Assistant's own dialog then asks the device's
            # name and area (and renames the entity ids), so the name is asked once.
            return self._create_entry(device.name or device.model)
        entry = self._get_reconfigure_entry()
        if device.serial or device.mac:
            self._abort_if_unique_id_mismatch()
        elif self.unique_id != entry.unique_id:
            # Without a serial or MAC the address is the identity: it may move, not collide.
            self._abort_if_unique_id_configured()
        return self._store(entry, "reconfigure_successful", self._data, unique_id=self.unique_id)

    def _store(
        self, entry: ConfigEntry, reason: str, data: dict[str, Any], **changes: Any
    ) -> ConfigFlowResult:
        """Update the entry, have it set up again exactly once, and end the flow.

        By its update listener when loaded and changed; else here, as this flow's own login
        (S7-200 SMART: one session per user) may have ended Home Assistant's session.
        """
        # Asked before the update: the listener starts the reload at once (not loaded after).
        listener_reloads = entry.state is ConfigEntryState.LOADED and entry.data != data
        self.hass.config_entries.async_update_entry(entry, data=data, **changes)
        if not listener_reloads:
            self.hass.config_entries.async_schedule_reload(entry.entry_id)
        return self.async_abort(reason=reason)

    async def _connect(self, data: Mapping[str, Any]) -> tuple[DeviceInfo | None, dict[str, str]]:
        """Connect and log in once; return what the PLC says, or the form errors."""
        client = create_client(self.hass, data)
        self._problem = ""
        try:
            device = await client.connect()
            await client.check_access()  # what writes need is refused here, on the form
            return device, {}
        except PlcError as err:
            LOGGER.debug("Cannot connect to %s: %s", data[CONF_HOST], err)
            self._problem = str(err)
            return None, error_for(err, type(client))
        except Exception:
            LOGGER.exception("Unexpected error connecting to %s", data[CONF_HOST])
            return None, {"base": "unknown"}
        finally:
            await client.close()

    def _connection_schema(self) -> vol.Schema:
        """Return the vendor's connection page; a reconfigure keeps the credentials as they are."""
        return connection_schema(
            client_class(self._vendor),
            self._vendor,
            credentials=self.source != SOURCE_RECONFIGURE,
        )

    def _connection_form(self, errors: dict[str, str]) -> ConfigFlowResult:
        """Show the vendor's connection page with the values entered so far."""
        schema = self._connection_schema()
        return self._form(
            connection_step(self._vendor, reconfigure=self.source == SOURCE_RECONFIGURE),
            schema,
            errors,
        )

    def _second_fields(self) -> set[str]:
        """The keys of the second page's fields, for the way chosen on the connection page."""
        return {field.key for field in second_page(self._vendor, self._data[CONF_OPTIONS])[1]}

    def _second_form(self, errors: dict[str, str]) -> ConfigFlowResult:
        """Show the second page: the fields of the way chosen on the connection page."""
        step_id, fields = second_page(self._vendor, self._data[CONF_OPTIONS])
        return self._form(step_id, vol.Schema(fields_schema(fields)), errors)

    def _form(self, step_id: str, schema: vol.Schema, errors: dict[str, str]) -> ConfigFlowResult:
        """Show a connection page, suggesting what was entered or stored before."""
        return self.async_show_form(
            step_id=step_id,
            data_schema=self.add_suggested_values_to_schema(
                schema, self._entered | form_values(self._data)
            ),
            errors=on_form(errors, schema),
            description_placeholders={"problem": self._problem},
        )
