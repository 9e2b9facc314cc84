"""Protocol-layer fixtures: simulators on loopback and clients connected to them."""

from __future__ import annotations

from collections.abc import AsyncGenerator, Callable
from typing import Any

import pytest

from custom_components.plc_bridge.plc import ConnectionConfig, TlsMode
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from simulators.s7_smart import DEFAULT_PASSWORD, DEFAULT_USER, S7SmartSimulator

# The other vendors' protocol fixtures, for the tests of this folder only: imported into this
# conftest, they override the Home Assistant tests' fixtures of the same names (which set up
# entries) here and nowhere else. (`pytest_plugins` in a test module would register them for
# the whole run, where the last module collected would win.)
from .plcnext_fixtures import plcnext_client, plcnext_config, plcnext_sim  # noqa: F401
from .softplc_fixtures import (  # noqa: F401
    softplc_client,
    softplc_reading,
    softplc_settings,
    softplc_sim,
    softplc_tls_sim,
)
from .tecomat_fixtures import tecomat_client, tecomat_config, tecomat_sim  # noqa: F401

type ConfigFactory = Callable[..., ConnectionConfig]


@pytest.fixture
async def s7_smart_sim() -> AsyncGenerator[S7SmartSimulator]:
    """An S7-200 SMART simulator on 127.0.0.1 (HTTPS with its own device CA)."""
    sim = S7SmartSimulator()
    await sim.start()
    yield sim
    await sim.stop()


@pytest.fixture
def s7_smart_config(s7_smart_sim: S7SmartSimulator) -> ConfigFactory:
    """Make the settings of a client of the simulator: pinned certificate, Prague clock."""

    def make(**changes: Any) -> ConnectionConfig:
        settings: dict[str, Any] = {
            "host": s7_smart_sim.host,
            "port": s7_smart_sim.port,
            "username": DEFAULT_USER,
            "password": DEFAULT_PASSWORD,
            "tls": TlsMode.PIN,
            "fingerprint": s7_smart_sim.fingerprint or "",
            "timeout": 5.0,
            "time_zone": "Europe/Prague",
        }
        return ConnectionConfig(**(settings | changes))

    return make


@pytest.fixture
async def s7_smart_client(s7_smart_config: ConfigFactory) -> AsyncGenerator[S7SmartClient]:
    """A client connected to the simulator (its own HTTP session), closed afterwards."""
    client = S7SmartClient(s7_smart_config())
    await client.connect()
    yield client
    await client.close()
