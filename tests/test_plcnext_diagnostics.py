"""Diagnostics of a PLCnext Control: what helps, never a credential, token or where it is."""

from __future__ import annotations

import logging

from freezegun.api import FrozenDateTimeFactory
from homeassistant.core import HomeAssistant
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from pytest_homeassistant_custom_component.components.diagnostics import (
    get_diagnostics_for_config_entry,
)
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from simulators.plcnext import DEFAULT_PASSWORD, PlcnextSimulator
from tests.entries import poll

REDACTED = "**REDACTED**"


def secrets_of(sim: PlcnextSimulator) -> list[str]:
    """Return what must never show: the password, access tokens, the certificate pin.

    (Session ids grant nothing without the token; the debug log shows them in URLs.)
    """
    assert sim.access.tokens
    return [DEFAULT_PASSWORD, sim.fingerprint or "", *sim.access.tokens]


async def test_diagnostics(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    plcnext_ha_sim: PlcnextSimulator,
    plcnext_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Settings, device, program checksum, one request per poll; secrets redacted."""
    plcnext_ha_sim.access.expire_tokens()  # a second login: two tokens made, neither shown
    plcnext_ha_sim.download({"Arp.Plc.Eclr/MainInstance.Alarm": "Arp.Plc.Eclr/MainInstance.Fault"})
    await poll(hass, freezer)
    result = await get_diagnostics_for_config_entry(hass, hass_client, plcnext_entry)
    entry = result["entry"]["data"]
    for key in ("username", "password", "host", "fingerprint"):
        assert entry[key] == REDACTED, key
    assert entry["vendor_options"] == {"clock_variable": "Arp.Plc.Eclr/MainInstance.Clock"}
    device = result["device"]
    assert device["model"] == "PLCnext Control"
    assert device["extra"]["api_path"] == "/_pxc_api/v1.8"
    assert device["extra"]["user_authentication"] == "on"
    assert result["status"]["extra"]["project_crc"] == str(plcnext_ha_sim.crc)
    assert result["poll"]["planned_requests"] == 1
    assert result["metrics"]["session_renewals"] == 1
    results = result["results"]
    assert results["Arp.Plc.Eclr/MainInstance.Temperature|REAL"] == {"ok": True, "value": 21.5}
    alarm = results["Arp.Plc.Eclr/MainInstance.Alarm|BOOL"]
    assert not alarm["ok"]
    assert "does not know this variable" in alarm["error"]
    text = str(result)
    for secret in [*secrets_of(plcnext_ha_sim), *plcnext_ha_sim.access.sessions, "127.0.0.1"]:
        assert secret not in text, secret


async def test_debug_log_hides_tokens(
    hass: HomeAssistant,
    plcnext_ha_sim: PlcnextSimulator,
    plcnext_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """With debug logging on, a login and polls show no password, code or access token."""
    caplog.set_level(logging.DEBUG, logger="custom_components.plc_bridge")
    plcnext_ha_sim.access.expire_tokens()
    await poll(hass, freezer)
    assert "POST" in caplog.text
    assert "auth/access-token" in caplog.text
    assert '"code": "***"' in caplog.text
    for secret in secrets_of(plcnext_ha_sim):
        assert secret not in caplog.text, secret
