"""A poll with the debug log off spends nothing on masking what it would log."""

from __future__ import annotations

import logging

import pytest

from custom_components.plc_bridge.plc import Point, http
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient

pytestmark = pytest.mark.no_pacing


async def test_no_masking_while_debug_is_off(
    s7_smart_client: S7SmartClient,
    monkeypatch: pytest.MonkeyPatch,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """Every body would be decoded and searched for secrets: only for a debug log that is on."""
    calls: list[object] = []
    original = http.shown

    def counting(body: str | bytes | None, *args: object) -> str:
        calls.append(body)
        return original(body, *args)  # type: ignore[arg-type]

    monkeypatch.setattr(http, "shown", counting)
    points = [Point(f"VW{2 * index}", "signed") for index in range(64)]
    with caplog.at_level(logging.INFO, logger="custom_components.plc_bridge.plc"):
        result = await s7_smart_client.read(points)
    assert all(outcome.ok for outcome in result.values.values())
    assert calls == []
    with caplog.at_level(logging.DEBUG, logger="custom_components.plc_bridge.plc"):
        await s7_smart_client.read(points)
    assert len(calls) == 4  # two requests, each body and reply
