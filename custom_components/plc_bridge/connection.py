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

from .const import CONF_FINGERPRINT, CONF_OPTIONS, CONF_TLS, CONF_VENDOR
from .plc import ConnectionConfig, PlcClient, TlsMode
from .plc.vendors import client_class


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
    """Return an unconnected client for entry data, on Home Assistant's shared HTTP session."""
    return client_class(data[CONF_VENDOR])(
        connection_config(hass, data, options), async_get_clientsession(hass)
    )
