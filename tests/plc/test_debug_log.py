"""Debug logging of requests and replies: what the PLC answered, never credentials or tokens."""

from __future__ import annotations

import hashlib
import logging

import pytest

from custom_components.plc_bridge.plc import ConnectionConfig, PlcConnectionError, Point, TlsMode
from custom_components.plc_bridge.plc.http import shown
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from simulators.s7_smart import DEFAULT_PASSWORD, DEFAULT_USER, S7SmartSimulator

pytestmark = pytest.mark.no_pacing


def test_shown_masks_credentials_and_cuts_long_bodies() -> None:
    """Passwords, user names and tokens are masked; a long body is cut with its length."""
    body = b'{"params": {"username": "admin", "password": "abc123"}, "result": {"token": "t0k"}}'
    text = shown(body)
    for secret in ("admin", "abc123", "t0k"):
        assert secret not in text
    assert '"password": "***"' in text
    tokens = shown('{"access_token":"a1","auth_token":"b2","refresh_token":"c3","expires_in":60}')
    assert tokens.count('"***"') == 3
    assert '"expires_in":60' in tokens
    assert shown("x" * 600).endswith("(600 characters)")
    assert shown(None) == ""


async def test_requests_and_replies_logged_without_secrets(
    caplog: pytest.LogCaptureFixture,
) -> None:
    """A login and a poll at debug level: methods and values shown, password, hash, token not."""
    sim = S7SmartSimulator()
    sim.set("VW10", 235)
    await sim.start()
    config = ConnectionConfig(
        host=sim.host,
        port=sim.port,
        username=DEFAULT_USER,
        password=DEFAULT_PASSWORD,
        tls=TlsMode.PIN,
        fingerprint=sim.fingerprint or "",
    )
    client = S7SmartClient(config)
    try:
        with caplog.at_level(logging.DEBUG, logger="custom_components.plc_bridge.plc"):
            await client.connect()
            result = await client.read([Point("VW10", "signed")])
            token = client._token or ""
    finally:
        await client.close()
        await sim.stop()
    assert result.values[Point("VW10", "signed")].value == 235
    text = caplog.text
    assert '"login"' in text
    assert "VW10" in text
    assert "235" in text
    hashed = hashlib.sha512(DEFAULT_PASSWORD.encode()).hexdigest()
    for secret in (DEFAULT_PASSWORD, hashed, token, DEFAULT_USER):
        assert secret
        assert secret not in text, secret


async def test_closed_port_message_names_no_python_object() -> None:
    """A pinned PLC that is away: the message says so, not `Fingerprint object at 0x…`."""
    sim = S7SmartSimulator()
    await sim.start()
    port, fingerprint = sim.port, sim.fingerprint or ""
    await sim.stop()
    config = ConnectionConfig(
        host="127.0.0.1", port=port, tls=TlsMode.PIN, fingerprint=fingerprint, timeout=2
    )
    client = S7SmartClient(config)
    try:
        with pytest.raises(PlcConnectionError) as caught:
            await client.connect()
    finally:
        await client.close()
    assert "object at 0x" not in str(caught.value)
    assert f"127.0.0.1:{port}" in str(caught.value)
