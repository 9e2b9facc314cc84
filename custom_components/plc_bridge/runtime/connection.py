"""Build a protocol client from a config entry's data; shared by the flow and the setup."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from homeassistant.const import (
    CONF_HOST,
    CONF_PASSWORD,
    CONF_PORT,
    CONF_SCAN_INTERVAL,
    CONF_USERNAME,
)
from homeassistant.core import HomeAssistant
from homeassistant.helpers.aiohttp_client import async_get_clientsession
from homeassistant.util.ssl import SSL_ALPN_HTTP11, client_context

from ..const import CONF_FINGERPRINT, CONF_OPTIONS, CONF_TLS, CONF_VENDOR
from ..plc import ConnectionConfig, PlcClient, TlsMode
from ..plc.http import client_session
from ..plc.vendors import client_class


def connection_config(
    hass: HomeAssistant, data: Mapping[str, Any], options: Mapping[str, Any] | None = None
) -> ConnectionConfig:
    """Return the protocol layer's connection settings for entry data (and options)."""
    vendor = client_class(data[CONF_VENDOR])
    interval = (options or {}).get(CONF_SCAN_INTERVAL, vendor.default_scan_interval)
    return ConnectionConfig(
        host=data[CONF_HOST],
        port=int(data[CONF_PORT]),
        username=data.get(CONF_USERNAME, ""),
        password=data.get(CONF_PASSWORD, ""),
        tls=TlsMode(data.get(CONF_TLS, TlsMode.NONE)),
        fingerprint=data.get(CONF_FINGERPRINT, ""),
        time_zone=str(hass.config.time_zone),
        poll_interval=float(interval),
        options=dict(data.get(CONF_OPTIONS, {})),
    )


def create_client(
    hass: HomeAssistant, data: Mapping[str, Any], options: Mapping[str, Any] | None = None
) -> PlcClient:
    """Return an unconnected client for a flow's checks, on Home Assistant's shared HTTP session."""
    return client_class(data[CONF_VENDOR], data.get(CONF_OPTIONS, {}))(
        connection_config(hass, data, options), async_get_clientsession(hass)
    )


def create_polling_client(
    hass: HomeAssistant, data: Mapping[str, Any], options: Mapping[str, Any] | None = None
) -> PlcClient:
    """Return an unconnected client for a set-up entry, on an HTTP session of its PLC's own.

    Home Assistant's shared connector closes a connection after 15 s idle (aiohttp's default),
    so at any longer poll interval every poll would open a new connection and, on HTTPS, pay a
    TLS handshake the PLC's small CPU feels (S7-200 SMART manual 4.2: "Use long connections").
    This session keeps it for the poll interval; certificates are checked as on the shared one.
    The client closes it with itself (`close`).
    """
    cls = client_class(data[CONF_VENDOR], data.get(CONF_OPTIONS, {}))
    config = connection_config(hass, data, options)
    if not cls.uses_http:
        return cls(config)
    client = cls(config, client_session(config, client_context(alpn_protocols=SSL_ALPN_HTTP11)))
    client.own_session()
    return client
