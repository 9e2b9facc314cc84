"""S7-200 SMART fixtures for the protocol tests: a Web API simulator and clients of it."""

from __future__ import annotations

from collections.abc import AsyncGenerator

import pytest

from custom_components.plc_bridge.plc import TlsMode
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from simulators.s7_smart import DEFAULT_PASSWORD, DEFAULT_USER, S7SmartSimulator
from tests.loopback import ConfigFactory, config_factory, connected, running

__all__ = ["ConfigFactory", "s7_smart_client", "s7_smart_config", "s7_smart_sim"]


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
