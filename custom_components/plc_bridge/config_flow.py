"""Config flow of PLC Bridge: vendor, connection and certificate, reauth and reconfigure."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from homeassistant.config_entries import (
    SOURCE_RECONFIGURE,
    ConfigEntry,
    ConfigEntryState,
    ConfigFlow,
    ConfigFlowResult,
    ConfigSubentryFlow,
)
from homeassistant.const import CONF_HOST, CONF_NAME, CONF_PASSWORD, CONF_PORT, CONF_USERNAME
from homeassistant.core import callback
from homeassistant.helpers.device_registry import format_mac
from homeassistant.helpers.selector import (
    NumberSelector,
    NumberSelectorConfig,
    NumberSelectorMode,
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
    TextSelector,
)
import voluptuous as vol

from .connection import create_client
from .connection_form import (
    CREDENTIALS_SCHEMA,
    VendorField,
    connection_data,
    connection_schema,
    error_for,
    form_values,
    on_form,
    vendor_options,
)
from .const import (
    CONF_FINGERPRINT,
    CONF_OPTIONS,
    CONF_TLS,
    CONF_VENDOR,
    DOMAIN,
    LOGGER,
    SUBENTRY_DEVICE,
)
from .options_flow import PlcBridgeOptionsFlow
from .plc import DeviceInfo, PlcError, PlcValueError, TlsMode
from .plc.http import fetch_fingerprint, format_fingerprint
from .plc.vendors import client_class, implemented
from .subentry_flow import DeviceSubentryFlowHandler

CERTIFICATE_TIMEOUT = 10.0
"""Seconds to wait for the PLC's TLS handshake when fetching its certificate."""


def _choice(key: str, options: list[str]) -> SelectSelector:
    """Return a translated select of fixed options."""
    return SelectSelector(
        SelectSelectorConfig(options=options, translation_key=key, mode=SelectSelectorMode.LIST)
    )


def _whole(low: int, high: int) -> NumberSelector:
    """Return a whole-number box."""
    return NumberSelector(
        NumberSelectorConfig(min=low, max=high, step=1, mode=NumberSelectorMode.BOX)
    )


VENDOR_FIELDS: dict[str, tuple[VendorField, ...]] = {
    "tecomat": (
        VendorField("auth", _choice("auth", ["digest", "basic"]), "digest"),
        VendorField("clock_variable", TextSelector()),
    ),
    "s7": (
        VendorField("family", _choice("family", ["s7_300_1500", "s7_200"]), "s7_300_1500"),
        VendorField("connection", _choice("connection", ["rack_slot", "tsap"]), "rack_slot"),
    ),
}
"""Extra connection fields per vendor key, shown after the TLS mode; labels in strings.json.

Whole numbers come back as int; the client checks them (`validate_options`) and reads them
from ConnectionConfig.options.
"""
ADDRESSING: dict[str, tuple[str, dict[str, tuple[VendorField, ...]]]] = {
    "s7": (
        "connection",
        {
            "rack_slot": (
                VendorField("rack", _whole(0, 7), 0),
                VendorField("slot", _whole(0, 31), 1),
            ),
            "tsap": (
                VendorField("local_tsap", TextSelector()),
                VendorField("remote_tsap", TextSelector()),
            ),
        },
    ),
}
"""Fields of a second form, by the vendor option that chooses them (S7: rack and slot, or TSAPs):
only the fields of the way chosen are asked."""


def device_unique_id(device: DeviceInfo, data: Mapping[str, Any]) -> str:
    """Return the entry's unique id: the serial or MAC, else host:port for devices without."""
    if device.serial:
        return device.serial
    if device.mac:
        return format_mac(device.mac)
    return f"{data[CONF_HOST]}:{data[CONF_PORT]}"


class PlcBridgeConfigFlow(ConfigFlow, domain=DOMAIN):
    """Add a PLC: vendor, connection, certificate; reauth and reconfigure reuse the checks."""

    VERSION = 2

    def __init__(self) -> None:
        """Start with nothing chosen and no certificate trusted."""
        self._vendor = ""
        self._data: dict[str, Any] = {}
        self._trusted: set[str] = set()
        self._problem = ""  # the protocol layer's words for the last failure, shown in errors
        self._name = ""  # what the PLC calls itself, offered as the entry's name
        self._previous: dict[str, Any] = {}  # the vendor options before this form, suggested
        self._step_id = "connection"  # the form that asked the connection: shown on errors

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
        """Return the subentry flows: a device of the plant, holding its points."""
        return {SUBENTRY_DEVICE: DeviceSubentryFlowHandler}

    async def async_step_user(self, user_input: dict[str, Any] | None = None) -> ConfigFlowResult:
        """Pick the vendor among those PLC Bridge implements."""
        if user_input is not None:
            self._vendor = user_input[CONF_VENDOR]
            self._data = {CONF_VENDOR: self._vendor, CONF_USERNAME: "", CONF_PASSWORD: ""}
            return await self.async_step_connection()
        schema = vol.Schema(
            {
                vol.Required(CONF_VENDOR): SelectSelector(
                    SelectSelectorConfig(
                        options=implemented(),
                        translation_key=CONF_VENDOR,
                        mode=SelectSelectorMode.LIST,
                    )
                )
            }
        )
        return self.async_show_form(step_id="user", data_schema=schema)

    async def async_step_name(self, user_input: dict[str, Any] | None = None) -> ConfigFlowResult:
        """Name the PLC (prefilled from what it reports): its device and entity ids take it."""
        if user_input is not None and str(user_input.get(CONF_NAME, "")).strip():
            return self.async_create_entry(
                title=str(user_input[CONF_NAME]).strip(), data=self._data
            )
        schema = vol.Schema({vol.Required(CONF_NAME): TextSelector()})
        return self.async_show_form(
            step_id="name",
            data_schema=self.add_suggested_values_to_schema(schema, {CONF_NAME: self._name}),
        )

    async def async_step_connection(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Ask where the PLC is and how to log in, then check the certificate and connect."""
        if user_input is None:
            return self._connection_form("connection", {})
        return await self._submit_connection("connection", user_input)

    async def async_step_reconfigure(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Change the address, TLS mode or vendor fields of a configured PLC."""
        if not self._data:
            entry = self._get_reconfigure_entry()
            self._vendor = entry.data[CONF_VENDOR]
            self._data = dict(entry.data)
            self._trusted.add(entry.data.get(CONF_FINGERPRINT, ""))
        if user_input is None:
            return self._connection_form("reconfigure", {})
        return await self._submit_connection("reconfigure", user_input)

    async def async_step_certificate(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
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

    async def async_step_reauth(self, entry_data: Mapping[str, Any]) -> ConfigFlowResult:
        """Start re-authentication after the PLC refused the stored credentials."""
        return await self.async_step_reauth_confirm()

    async def async_step_reauth_confirm(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Ask for the credentials again and check them before storing."""
        entry = self._get_reauth_entry()
        errors: dict[str, str] = {}
        if user_input is not None:
            data = {**entry.data, **user_input}
            device, errors = await self._connect(data)
            if device is not None:
                return self._store(entry, "reauth_successful", data=data)
        return self.async_show_form(
            step_id="reauth_confirm",
            data_schema=self.add_suggested_values_to_schema(
                CREDENTIALS_SCHEMA, {CONF_USERNAME: entry.data.get(CONF_USERNAME)}
            ),
            errors=on_form(errors, CREDENTIALS_SCHEMA),
            description_placeholders={"name": entry.title, "problem": self._problem},
        )

    async def _submit_connection(
        self, step_id: str, user_input: dict[str, Any]
    ) -> ConfigFlowResult:
        """Take a submitted connection form: fetch the certificate in pin mode, then connect."""
        client = client_class(self._vendor)
        extras = VENDOR_FIELDS.get(self._vendor, ())
        self._previous = dict(self._data.get(CONF_OPTIONS, {}))
        self._data.update(connection_data(client, extras, user_input))
        self._step_id = step_id
        if self._vendor in ADDRESSING:
            return await self.async_step_addressing()
        return await self._check_and_connect(step_id)

    def _addressing_fields(self) -> tuple[VendorField, ...]:
        """The second form's fields for the way the first form chose."""
        choice, ways = ADDRESSING[self._vendor]
        return ways[str(self._data[CONF_OPTIONS].get(choice, next(iter(ways))))]

    async def async_step_addressing(
        self, user_input: dict[str, Any] | None = None, errors: dict[str, str] | None = None
    ) -> ConfigFlowResult:
        """Ask only the fields of the chosen way to address the PLC (S7: rack/slot or TSAPs)."""
        fields = self._addressing_fields()
        if user_input is not None:
            self._data[CONF_OPTIONS] |= vendor_options(fields, user_input)
            return await self._check_and_connect(self._step_id)
        schema = vol.Schema(
            {
                (
                    vol.Optional(field.key)
                    if field.default is None
                    else vol.Required(field.key, default=field.default)
                ): field.selector
                for field in fields
            }
        )
        return self.async_show_form(
            step_id="addressing",
            data_schema=self.add_suggested_values_to_schema(schema, self._previous),
            errors=errors or {},
            description_placeholders={"problem": self._problem},
        )

    async def _check_and_connect(self, step_id: str) -> ConfigFlowResult:
        """Check the vendor options, fetch the certificate in pin mode, then connect."""
        client = client_class(self._vendor)
        try:
            self._data[CONF_OPTIONS] = client.validate_options(self._data[CONF_OPTIONS])
        except PlcValueError as err:
            self._problem = str(err)
            if self._vendor in ADDRESSING:
                return await self.async_step_addressing(errors={"base": "invalid_options"})
            return self._connection_form(step_id, {"base": "invalid_options"})
        self._data[CONF_FINGERPRINT] = ""
        if self._data[CONF_TLS] == TlsMode.PIN:
            try:
                self._data[CONF_FINGERPRINT] = await fetch_fingerprint(
                    self._data[CONF_HOST], self._data[CONF_PORT], CERTIFICATE_TIMEOUT
                )
            except PlcError as err:
                self._problem = str(err)
                return self._connection_form(step_id, error_for(err))
            if self._data[CONF_FINGERPRINT] not in self._trusted:
                return await self.async_step_certificate()
        return await self._finish()

    async def _finish(self) -> ConfigFlowResult:
        """Connect with the gathered settings, then create or update the entry."""
        device, errors = await self._connect(self._data)
        if device is None:
            step_id = "reconfigure" if self.source == SOURCE_RECONFIGURE else "connection"
            return self._connection_form(step_id, errors)
        await self.async_set_unique_id(
            device_unique_id(device, self._data), raise_on_progress=False
        )
        if self.source != SOURCE_RECONFIGURE:
            self._abort_if_unique_id_configured()
            self._name = device.name or device.model
            return await self.async_step_name()
        entry = self._get_reconfigure_entry()
        if device.serial or device.mac:
            self._abort_if_unique_id_mismatch()
        elif self.unique_id != entry.unique_id:
            # Without a serial or MAC the address is the identity: it may move, not collide.
            self._abort_if_unique_id_configured()
        return self._store(
            entry, "reconfigure_successful", data=self._data, unique_id=self.unique_id
        )

    def _store(self, entry: ConfigEntry, reason: str, **changes: Any) -> ConfigFlowResult:
        """Update the entry and end the flow; the update listener reloads a loaded entry.

        An entry whose setup failed (wrong password, PLC away) has no listener yet: it is
        reloaded here, so new credentials or a new address take effect at once.
        """
        # Asked before the update: the update listener starts the reload of a loaded entry at
        # once, so afterwards it no longer looks loaded, and a second reload would follow.
        loaded = entry.state is ConfigEntryState.LOADED
        self.hass.config_entries.async_update_entry(entry, **changes)
        if not loaded:
            self.hass.config_entries.async_schedule_reload(entry.entry_id)
        return self.async_abort(reason=reason)

    async def _connect(self, data: Mapping[str, Any]) -> tuple[DeviceInfo | None, dict[str, str]]:
        """Connect and log in once; return what the PLC says, or the form errors."""
        client = create_client(self.hass, data)
        self._problem = ""
        try:
            return await client.connect(), {}
        except PlcError as err:
            LOGGER.debug("Cannot connect to %s: %s", data[CONF_HOST], err)
            self._problem = str(err)
            return None, error_for(err)
        except Exception:
            LOGGER.exception("Unexpected error connecting to %s", data[CONF_HOST])
            return None, {"base": "unknown"}
        finally:
            await client.close()

    def _connection_form(self, step_id: str, errors: dict[str, str]) -> ConfigFlowResult:
        """Show the connection (or reconfigure) form with the values entered so far."""
        schema = connection_schema(
            client_class(self._vendor),
            VENDOR_FIELDS.get(self._vendor, ()),
            credentials=step_id == "connection",
        )
        return self.async_show_form(
            step_id=step_id,
            data_schema=self.add_suggested_values_to_schema(schema, form_values(self._data)),
            errors=on_form(errors, schema),
            description_placeholders={"problem": self._problem},
        )
