"""Fixtures shared by every test: custom integrations on, loopback sockets, no request pacing."""

from __future__ import annotations

import pytest

from custom_components.plc_bridge.plc.vendors import client_class, implemented

pytest_plugins = [
    "tests.flow_fixtures",
    "tests.ha_fixtures",
    "tests.tecomat_ha_fixtures",
    "tests.s7_ha_fixtures",
]


@pytest.fixture(autouse=True)
def auto_enable_custom_integrations(enable_custom_integrations: None) -> None:
    """Let Home Assistant load custom_components/plc_bridge in every test."""


@pytest.fixture(autouse=True)
def loopback(socket_enabled: None) -> None:
    """Tests talk to the simulators over real loopback sockets."""


@pytest.fixture(autouse=True)
def no_pacing(monkeypatch: pytest.MonkeyPatch) -> None:
    """Drop the vendors' advised pause between requests so tests run at full speed."""
    for vendor in implemented():
        monkeypatch.setattr(client_class(vendor), "request_interval", 0.0)
