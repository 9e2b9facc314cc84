"""Fixtures shared by every test: custom integrations on, loopback sockets; pacing off on request.

And no test passes while Home Assistant reports a deprecated use by the integration.
"""

from __future__ import annotations

import asyncio
from collections.abc import AsyncGenerator, Generator
from typing import Any

from homeassistant.const import MAJOR_VERSION, MINOR_VERSION
from homeassistant.core import HomeAssistant
import pytest
from pytest_homeassistant_custom_component.syrupy import HomeAssistantSnapshotExtension
from syrupy.assertion import SnapshotAssertion

from custom_components.plc_bridge.plc.vendors import client_class, implemented

pytest_plugins = ["tests.flows.forms", "tests.entries", "tests.harness"]


@pytest.fixture(autouse=True)
def auto_enable_custom_integrations(enable_custom_integrations: None) -> None:
    """Let Home Assistant load custom_components/plc_bridge in every test."""


@pytest.fixture(autouse=True)
def loopback(socket_enabled: None) -> None:
    """Tests talk to the simulators over real loopback sockets."""


def pytest_configure(config: pytest.Config) -> None:
    """Register the `no_pacing` marker."""
    config.addinivalue_line(
        "markers", "no_pacing: the vendors' request pacing is off (the test runs at full speed)"
    )


@pytest.fixture(autouse=True)
def pacing_as_asked(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> None:
    """Drop the vendors' advised pause between requests where the test or its module asks.

    Asked with the `no_pacing` marker (`pytestmark = pytest.mark.no_pacing` in a module), never
    for all: the tests that pin the pacing and those of paced behaviour see the real one. An
    autouse fixture, so that it comes before any fixture that connects a client. A test under
    Home Assistant's frozen clock needs it where a paced vendor sends requests.
    """
    if request.node.get_closest_marker("no_pacing") is None:
        return
    for vendor in implemented():
        monkeypatch.setattr(client_class(vendor), "request_interval", 0.0)


CURRENT_RELEASE = (MAJOR_VERSION, MINOR_VERSION) >= (2026, 10)
current_release_only = pytest.mark.skipif(
    not CURRENT_RELEASE,
    reason="snapshots hold the current release's registry fields; older releases have fewer",
)
"""Mark for snapshot tests: the snapshots are taken on the current Home Assistant."""

HANDSHAKE_REFUSED = "Error on transport creation for incoming connection"


@pytest.fixture(autouse=True)
async def refused_handshakes_are_expected(hass: HomeAssistant) -> AsyncGenerator[None]:
    """A TLS handshake a client refuses (a certificate not trusted) is no error of the test.

    In debug mode, as Home Assistant's tests run the loop, asyncio reports it for a server's
    incoming connection; the simulator is the server here, and the refusal is what the
    verify and pin tests ask for. Everything else still fails the test.
    """
    loop = asyncio.get_running_loop()
    handler = loop.get_exception_handler()

    def filtered(loop: asyncio.AbstractEventLoop, context: dict[str, Any]) -> None:
        if context.get("message") != HANDSHAKE_REFUSED and handler is not None:
            handler(loop, context)

    loop.set_exception_handler(filtered)
    yield
    loop.set_exception_handler(handler)


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
