"""Fixtures shared by every test: custom integrations on, loopback sockets, no request pacing.

And no test passes while Home Assistant reports a deprecated use by the integration.
"""

from __future__ import annotations

from collections.abc import Generator

from homeassistant.const import MAJOR_VERSION, MINOR_VERSION
import pytest
from pytest_homeassistant_custom_component.syrupy import HomeAssistantSnapshotExtension
from syrupy.assertion import SnapshotAssertion

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


CURRENT_RELEASE = (MAJOR_VERSION, MINOR_VERSION) >= (2026, 10)
current_release_only = pytest.mark.skipif(
    not CURRENT_RELEASE,
    reason="snapshots hold the current release's registry fields; older releases have fewer",
)
"""Mark for snapshot tests: the snapshots are taken on the current Home Assistant."""

DEPRECATED_USE = "Detected that custom integration 'plc_bridge'"


@pytest.fixture(autouse=True)
def no_deprecated_use(caplog: pytest.LogCaptureFixture) -> Generator[None]:
    """Fail a test whose log has Home Assistant's report of a deprecated use by PLC Bridge."""
    yield
    reports = [
        record.getMessage()
        for when in ("setup", "call")
        for record in caplog.get_records(when)
        if DEPRECATED_USE in record.getMessage()
    ]
    assert not reports, "Home Assistant reports a deprecated use:\n" + "\n".join(reports)


@pytest.fixture
def snapshot(snapshot: SnapshotAssertion) -> SnapshotAssertion:
    """Home Assistant's snapshot extension (the newest harness leaves syrupy's plain one)."""
    return snapshot.use_extension(HomeAssistantSnapshotExtension)
