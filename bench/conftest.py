"""Fixtures of the Home Assistant part of the benchmarks (run only through scripts/bench)."""

from __future__ import annotations

import pytest

from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient

pytest_plugins = ["tests.entries", "tests.harness"]


@pytest.fixture(autouse=True)
def auto_enable_custom_integrations(enable_custom_integrations: None) -> None:
    """Let Home Assistant load custom_components/plc_bridge."""


@pytest.fixture(autouse=True)
def loopback(socket_enabled: None) -> None:
    """The benchmark talks to the simulator over real loopback sockets."""


@pytest.fixture(autouse=True)
def no_pacing(monkeypatch: pytest.MonkeyPatch) -> None:
    """Poll at full speed: the figures are the protocol's cost, not the advised request rate."""
    monkeypatch.setattr(S7SmartClient, "request_interval", 0.0)
