"""S7-200 SMART fixtures for the protocol tests: a Web API simulator and clients of it."""

from __future__ import annotations

from collections.abc import AsyncGenerator
from typing import Any

import pytest

from custom_components.plc_bridge.plc import TlsMode
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient, rpc
from simulators.s7_smart import CODES, DEFAULT_PASSWORD, DEFAULT_USER, S7SmartSimulator
from tests.loopback import ConfigFactory, config_factory, connected, running

__all__ = [
    "FIRMWARES",
    "ConfigFactory",
    "configure",
    "fast_backoff",
    "firmware_id",
    "s7_smart_client",
    "s7_smart_config",
    "s7_smart_sim",
]

FIRMWARES = [
    {"codes": codes, "stop_refusal": stop, "error_status": status, "cookie_name_in_token": named}
    for codes in CODES
    for stop in ("request", "node")
    for status, named in ((200, True), (500, False))  # each value of both, in pairs
]
"""The readings a firmware takes of what the manual leaves open (READINGS.md rows 1-10)."""


def configure(sim: S7SmartSimulator, firmware: dict[str, Any]) -> None:
    """Set the simulator's switches for the readings a firmware takes (READINGS.md)."""
    for name, value in firmware.items():
        setattr(sim, name, value)


def firmware_id(firmware: dict[str, Any]) -> str:
    """Name a firmware's readings in a test id."""
    return (
        f"{firmware['codes']}-stop-{firmware['stop_refusal']}-http-{firmware['error_status']}"
        + ("" if firmware["cookie_name_in_token"] else "-bare-token")
    )


def fast_backoff(monkeypatch: pytest.MonkeyPatch) -> None:
    """Shorten the first wait before a busy read is sent again (1 s, the manual's pacing)."""
    monkeypatch.setattr(rpc, "BUSY_BACKOFF", 0.01)


@pytest.fixture
async def s7_smart_sim() -> AsyncGenerator[S7SmartSimulator]:
    """An S7-200 SMART simulator on 127.0.0.1 (HTTPS with its own device CA)."""
    async with running(S7SmartSimulator()) as sim:
        yield sim


@pytest.fixture
def s7_smart_config(s7_smart_sim: S7SmartSimulator) -> ConfigFactory:
    """Make the settings of a client of the simulator: pinned certificate, Prague clock."""
    return config_factory(
        s7_smart_sim,
        username=DEFAULT_USER,
        password=DEFAULT_PASSWORD,
        tls=TlsMode.PIN,
        timeout=5.0,
        time_zone="Europe/Prague",
    )


@pytest.fixture
async def s7_smart_client(s7_smart_config: ConfigFactory) -> AsyncGenerator[S7SmartClient]:
    """A client connected to the simulator (its own HTTP session), closed afterwards."""
    async with connected(S7SmartClient(s7_smart_config())) as client:
        yield client
