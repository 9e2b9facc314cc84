"""The connection form of the config flow: its fields, and the errors a connection attempt gives."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_PORT, CONF_USERNAME
from homeassistant.helpers.selector import (
    NumberSelector,
    NumberSelectorConfig,
    NumberSelectorMode,
    Selector,
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
    TextSelector,
    TextSelectorConfig,
    TextSelectorType,
)
import voluptuous as vol

from .const import CONF_OPTIONS, CONF_TLS
from .plc import (
    PlcAuthenticationError,
    PlcClient,
    PlcConnectionError,
    PlcError,
    PlcTimeoutError,
    PlcTlsError,
    TlsMode,
)


@dataclass(frozen=True, slots=True)
class VendorField:
    """A vendor-only field of the connection form, kept in entry.data["vendor_options"]."""

    key: str
    selector: Selector[Any]
    default: str | int | bool | None = None  # None: an optional field


CREDENTIALS_SCHEMA = vol.Schema(
    {
        vol.Required(CONF_USERNAME): TextSelector(TextSelectorConfig(autocomplete="username")),
        vol.Required(CONF_PASSWORD): TextSelector(
            TextSelectorConfig(type=TextSelectorType.PASSWORD, autocomplete="current-password")
        ),
    }
)


def connection_schema(
    client: type[PlcClient], extras: Sequence[VendorField], *, credentials: bool
) -> vol.Schema:
    """Return the connection form of a vendor: address, TLS mode, credentials, vendor fields."""
    fields: dict[vol.Marker, Any] = {
        vol.Required(CONF_HOST): TextSelector(),
        vol.Required(CONF_PORT, default=client.default_port): NumberSelector(
            NumberSelectorConfig(min=1, max=65535, mode=NumberSelectorMode.BOX)
        ),
    }
    if len(client.tls_modes) > 1:
        fields[vol.Required(CONF_TLS, default=client.default_tls.value)] = SelectSelector(
            SelectSelectorConfig(
                options=[mode.value for mode in client.tls_modes],
                translation_key=CONF_TLS,
                mode=SelectSelectorMode.LIST,
            )
        )
    if credentials and client.needs_credentials:
        fields.update(CREDENTIALS_SCHEMA.schema)
    for field in extras:
        marker = (
            vol.Optional(field.key)
            if field.default is None
            else vol.Required(field.key, default=field.default)
        )
        fields[marker] = field.selector
    return vol.Schema(fields)


def connection_data(
    client: type[PlcClient], extras: Sequence[VendorField], user_input: Mapping[str, Any]
) -> dict[str, Any]:
    """Return the entry data a submitted connection form sets (not the fingerprint)."""
    data: dict[str, Any] = {
        CONF_HOST: str(user_input[CONF_HOST]).strip(),
        CONF_PORT: int(user_input[CONF_PORT]),
        CONF_TLS: TlsMode(user_input.get(CONF_TLS, client.default_tls)).value,
        CONF_OPTIONS: vendor_options(extras, user_input),
    }
    if CONF_USERNAME in user_input:
        data[CONF_USERNAME] = user_input[CONF_USERNAME]
        data[CONF_PASSWORD] = user_input[CONF_PASSWORD]
    return data


def vendor_options(extras: Sequence[VendorField], user_input: Mapping[str, Any]) -> dict[str, Any]:
    """Return the vendor fields a form submitted, whole numbers as int."""
    return {field.key: _plain(user_input[field.key]) for field in extras if field.key in user_input}


def _plain(value: Any) -> Any:
    """Return a whole float from a number selector as int; anything else unchanged."""
    return int(value) if isinstance(value, float) and value.is_integer() else value


def form_values(data: Mapping[str, Any]) -> dict[str, Any]:
    """Return entry data flattened into the connection form's suggested values."""
    return {**data, **data.get(CONF_OPTIONS, {})}


def on_form(errors: dict[str, str], schema: vol.Schema) -> dict[str, str]:
    """Move errors about fields the form does not show to the form's base error."""
    shown = {str(marker) for marker in schema.schema}
    return {(field if field in shown else "base"): key for field, key in errors.items()}


def error_for(err: PlcError) -> dict[str, str]:
    """Return the form error for a failure to reach or log in to the PLC, on its field."""
    if isinstance(err, PlcAuthenticationError):
        return {CONF_PASSWORD: "invalid_auth"}
    if isinstance(err, PlcTlsError):
        return {CONF_TLS: "tls_failed"}
    if isinstance(err, PlcTimeoutError):
        return {CONF_HOST: "timeout"}
    if isinstance(err, PlcConnectionError):
        return {CONF_HOST: "cannot_connect"}
    return {"base": "protocol_error"}
