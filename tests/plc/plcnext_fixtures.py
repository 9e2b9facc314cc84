"""PLCnext fixtures for the protocol tests: a REST interface simulator and clients of it."""

from __future__ import annotations

from collections.abc import AsyncGenerator, Callable
from typing import Any

import pytest

from custom_components.plc_bridge.plc import ConnectionConfig, TlsMode
from custom_components.plc_bridge.plc.vendors.plcnext import PlcnextClient
from simulators.plcnext import DEFAULT_PASSWORD, DEFAULT_USER, PlcnextSimulator

type ConfigFactory = Callable[..., ConnectionConfig]


@pytest.fixture(params=[False, True], ids=["documented", "foreign"])
async def plcnext_sim(request: pytest.FixtureRequest) -> AsyncGenerator[PlcnextSimulator]:
    """A PLCnext simulator on 127.0.0.1 (HTTPS, user authentication on), in both error modes.

    "foreign" answers what the sources leave open with other reasons and error shapes.
    """
    sim = PlcnextSimulator(foreign=request.param)
    await sim.start()
    yield sim
    await sim.stop()


@pytest.fixture
def plcnext_config(plcnext_sim: PlcnextSimulator) -> ConfigFactory:
    """Make the settings of a client of the simulator: pinned certificate, Prague clock."""

    def make(**changes: Any) -> ConnectionConfig:
        settings: dict[str, Any] = {
            "host": plcnext_sim.host,
            "port": plcnext_sim.port,
            "username": DEFAULT_USER,
            "password": DEFAULT_PASSWORD,
            "tls": TlsMode.PIN,
            "fingerprint": plcnext_sim.fingerprint or "",
            "timeout": 5.0,
            "time_zone": "Europe/Prague",
            "options": {"clock_variable": "MainInstance.Clock"},
        }
        return ConnectionConfig(**(settings | changes))

    return make


@pytest.fixture
async def plcnext_client(plcnext_config: ConfigFactory) -> AsyncGenerator[PlcnextClient]:
    """A client connected to the simulator (its own HTTP session), closed afterwards."""
    client = PlcnextClient(plcnext_config())
    await client.connect()
    yield client
    await client.close()
