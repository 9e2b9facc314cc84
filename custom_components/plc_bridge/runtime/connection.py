"""Build a protocol client from a config entry's data; shared by the flow and the setup."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from homeassistant.core import HomeAssistant
from homeassistant.helpers.aiohttp_client import async_get_clientsession
from homeassistant.util.ssl import SSL_ALPN_HTTP11, client_context

from ..model.plc_config import Connection, PollOptions
from ..plc import ConnectionConfig, PlcClient, TlsMode
from ..plc.http import client_session
from ..plc.vendors import client_class


def connection_config(
    hass: HomeAssistant, data: Mapping[str, Any], options: Mapping[str, Any] | None = None
) -> ConnectionConfig:
    """Return the protocol layer's connection settings for entry data (and options)."""
    stored = Connection.from_data(data)
    interval = PollOptions.from_options(options or {}).scan_interval
    return ConnectionConfig(
        host=stored.host,
        port=int(stored.port),
        username=stored.username or "",
        password=stored.password or "",
        tls=TlsMode(stored.tls),
        fingerprint=stored.fingerprint or "",
        time_zone=str(hass.config.time_zone),
        poll_interval=float(interval or client_class(stored.vendor).default_scan_interval),
        options=dict(stored.vendor_options or {}),
    )


def create_client(
    hass: HomeAssistant, data: Mapping[str, Any], options: Mapping[str, Any] | None = None
) -> PlcClient:
    """Return an unconnected client for a flow's checks, on Home Assistant's shared HTTP session."""
    return _client_class(data)(
        connection_config(hass, data, options), async_get_clientsession(hass)
    )


def _client_class(data: Mapping[str, Any]) -> type[PlcClient]:
    """Return the client class of the entry's PLC, its address checks bound to its options."""
    stored = Connection.from_data(data)
    return client_class(stored.vendor, stored.vendor_options or {})


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
    cls = _client_class(data)
    config = connection_config(hass, data, options)
    if not cls.uses_http:
        return cls(config)
    client = cls(config, client_session(config, client_context(alpn_protocols=SSL_ALPN_HTTP11)))
    client.own_session()
    return client
