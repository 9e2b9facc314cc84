"""The connection forms of the config flow, one set per vendor, and the errors a connection gives.

Each vendor's forms have step ids of their own (`connection_s7`, `reconfigure_s7`, `s7_tsap`),
so that strings.json words each form for its PLC family alone.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import Any

from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_PORT, CONF_USERNAME
from homeassistant.helpers.selector import (
    NumberSelector,
    NumberSelectorConfig,
    NumberSelectorMode,
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
    TextSelector,
    TextSelectorConfig,
    TextSelectorType,
)
import voluptuous as vol

from ..const import CONF_OPTIONS, CONF_TLS, CONF_VENDOR
from ..model.plc_config import Problem
from ..model.vendor_fields import SECOND_PAGES, VENDOR_FIELDS, VendorField, choice
from ..plc import (
    PlcAuthenticationError,
    PlcClient,
    PlcConnectionError,
    PlcError,
    PlcSessionRefusedError,
    PlcTimeoutError,
    PlcTlsError,
)
from ..plc.vendors import implemented

CREDENTIALS_SCHEMA = vol.Schema(
    {
        vol.Required(CONF_USERNAME): TextSelector(TextSelectorConfig(autocomplete="username")),
        vol.Required(CONF_PASSWORD): TextSelector(
            TextSelectorConfig(type=TextSelectorType.PASSWORD, autocomplete="current-password")
        ),
    }
)


def vendor_schema(*others: str, vendors: list[str] | None = None) -> vol.Schema:
    """Return the first page: the PLC family, among those PLC Bridge implements, or `others`.

    Given `vendors` (those a discovered PLC answers), only those, the first preselected.
    """
    if vendors is None:
        return vol.Schema(
            {vol.Required(CONF_VENDOR): choice(CONF_VENDOR, [*implemented(), *others])}
        )
    return vol.Schema({vol.Required(CONF_VENDOR, default=vendors[0]): choice(CONF_VENDOR, vendors)})


def connection_step(vendor: str, *, reconfigure: bool) -> str:
    """Return the step id of a vendor's connection page (adding the PLC, or reconfiguring it)."""
    return f"{'reconfigure' if reconfigure else 'connection'}_{vendor}"


def second_page(vendor: str, options: Mapping[str, Any]) -> tuple[str, tuple[VendorField, ...]]:
    """Return the step id and fields of the second page the options chose; () without one."""
    page = SECOND_PAGES.get(vendor)
    if page is None:
        return "", ()
    way = str(options.get(page.choice, ""))
    if way not in page.ways:
        way = next(iter(page.ways))
    return f"{vendor}_{way}", page.ways[way]


def refused_field(vendor: str, data: Mapping[str, Any], errors: Mapping[str, str]) -> str | None:
    """Return the second page's field to blame for a session the PLC refused, if any.

    The client tells it (PlcSessionRefusedError): the PLC took the connection but refused the
    way chosen on the second page (a wrong slot or TSAP).
    """
    page = SECOND_PAGES.get(vendor)
    if page is None or errors.get(CONF_HOST) != "session_refused":
        return None
    return page.refused_on[second_page(vendor, data[CONF_OPTIONS])[0].removeprefix(f"{vendor}_")]


def fields_schema(fields: Sequence[VendorField]) -> dict[vol.Marker, Any]:
    """Return the markers and selectors of vendor fields; those without a default are optional."""
    return {
        (
            vol.Optional(field.key)
            if field.default is None
            else vol.Required(field.key, default=field.default)
        ): field.selector
        for field in fields
    }


def connection_schema(client: type[PlcClient], vendor: str, *, credentials: bool) -> vol.Schema:
    """Return a vendor's connection page: address, TLS mode, credentials, vendor fields."""
    fields: dict[vol.Marker, Any] = {
        vol.Required(CONF_HOST): TextSelector(),
        # Unbounded here: the model refuses a port out of range on its field (`Connection`).
        vol.Required(CONF_PORT, default=client.default_port): NumberSelector(
            NumberSelectorConfig(mode=NumberSelectorMode.BOX)
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
        fields.update(
            {vol.Optional(str(key)): value for key, value in CREDENTIALS_SCHEMA.schema.items()}
            if client.credentials_optional
            else CREDENTIALS_SCHEMA.schema
        )
    fields.update(fields_schema(VENDOR_FIELDS.get(vendor, ())))
    return vol.Schema(fields)


def connection_data(
    client: type[PlcClient],
    vendor: str,
    user_input: Mapping[str, Any],
    stored: Mapping[str, Any] | None = None,
) -> dict[str, Any]:
    """Return the entry data a submitted connection page sets (not the fingerprint), unchecked.

    The model checks it (`Connection.problems`): a port that is not whole stays as given.

    Vendor fields that are secrets, left empty, keep their `stored` values (a reconfigured
    SoftPLC keeps its client certificate and key unless new ones are pasted).
    """
    kept = {
        field.key: (stored or {})[field.key]
        for field in VENDOR_FIELDS.get(vendor, ())
        if field.credential and field.key not in user_input and field.key in (stored or {})
    }
    data: dict[str, Any] = {
        CONF_HOST: str(user_input[CONF_HOST]).strip(),
        CONF_PORT: _plain(user_input[CONF_PORT]),
        CONF_TLS: str(user_input.get(CONF_TLS, client.default_tls.value)),
        CONF_OPTIONS: kept | vendor_options(VENDOR_FIELDS.get(vendor, ()), user_input),
    }
    if CONF_USERNAME in user_input or CONF_PASSWORD in user_input:
        # Optional credentials (PLCnext): a field left empty is not sent at all.
        data[CONF_USERNAME] = user_input.get(CONF_USERNAME, "")
        data[CONF_PASSWORD] = user_input.get(CONF_PASSWORD, "")
    return data


def vendor_options(fields: Sequence[VendorField], user_input: Mapping[str, Any]) -> dict[str, Any]:
    """Return the vendor fields a form submitted, whole numbers as int."""
    return {field.key: _plain(user_input[field.key]) for field in fields if field.key in user_input}


def _plain(value: Any) -> Any:
    """Return a whole float from a number selector as int; anything else unchanged."""
    return int(value) if isinstance(value, float) and value.is_integer() else value


def form_values(data: Mapping[str, Any]) -> dict[str, Any]:
    """Return entry data flattened into the connection forms' suggested values (no secrets)."""
    secret = {
        field.key for fields in VENDOR_FIELDS.values() for field in fields if field.credential
    }
    options = {key: value for key, value in data.get(CONF_OPTIONS, {}).items() if key not in secret}
    return {**data, **options}


def on_form(errors: dict[str, str], schema: vol.Schema) -> dict[str, str]:
    """Move errors about fields the form does not show to the form's base error."""
    shown = {str(marker) for marker in schema.schema}
    return {(field if field in shown else "base"): key for field, key in errors.items()}


def problem_errors(problems: Iterable[Problem]) -> dict[str, str]:
    """Return the form errors of the model's problems: each on its field, else on the form."""
    errors: dict[str, str] = {}
    for problem in problems:
        errors.setdefault(problem.field or "base", problem.field_key)
    return errors


def error_for(err: PlcError, client: type[PlcClient] | None = None) -> dict[str, str]:
    """Return the form error for a failure to reach or log in to the PLC, on its field.

    A refused login is shown on the password, or on the option that authenticates instead
    (SoftPLC's client certificate).
    """
    if isinstance(err, PlcAuthenticationError):
        field = client.credential_option if client is not None else None
        return {field or CONF_PASSWORD: "invalid_auth"}
    if isinstance(err, PlcTlsError):
        return {CONF_TLS: "tls_failed"}
    if isinstance(err, PlcTimeoutError):
        return {CONF_HOST: "timeout"}
    if isinstance(err, PlcSessionRefusedError):
        return {CONF_HOST: "session_refused"}
    if isinstance(err, PlcConnectionError):
        return {CONF_HOST: "cannot_connect"}
    return {"base": "protocol_error"}
