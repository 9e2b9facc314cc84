"""The debug log's mask holds past escaped quotes, and costs nothing while debug is off."""

from __future__ import annotations

import logging

import pytest

from custom_components.plc_bridge.plc import ConnectionConfig, Point, TlsMode, http
from custom_components.plc_bridge.plc.http import shown
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from simulators.s7_smart import DEFAULT_PASSWORD, DEFAULT_USER, S7SmartSimulator

pytestmark = pytest.mark.no_pacing


def test_mask_runs_past_an_escaped_quote() -> None:
    """A password holding `\\"` is masked whole, not up to its escaped quote."""
    text = shown('{"password": "ab\\"cd-tail-secret", "id": 7}')
    assert "tail-secret" not in text
    assert '"password": "***"' in text
    assert '"id": 7' in text


def test_mask_of_a_body_cut_short() -> None:
    """An unterminated secret (a truncated reply) is masked to the end."""
    assert "half-a-token" not in shown('{"token": "half-a-token')


async def test_no_debug_text_while_debug_is_off(
    caplog: pytest.LogCaptureFixture, monkeypatch: pytest.MonkeyPatch
) -> None:
    """With debug logging off no body is masked or cut for a log line; with it on, each is."""
    calls: list[object] = []

    def counted(body: object, *args: object) -> str:
        calls.append(body)
        return shown(body, *args)  # type: ignore[arg-type]

    monkeypatch.setattr(http, "shown", counted)
    sim = S7SmartSimulator()
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
        with caplog.at_level(logging.INFO, logger="custom_components.plc_bridge.plc"):
            await client.connect()
            await client.read([Point("VW10", "signed")])
        assert calls == []
        with caplog.at_level(logging.DEBUG, logger="custom_components.plc_bridge.plc"):
            await client.read([Point("VW10", "signed")])
        assert calls
    finally:
        await client.close()
        await sim.stop()
