"""Tecomat fixtures for the protocol tests: a TecoApi simulator and clients of it."""

from __future__ import annotations

from collections.abc import AsyncGenerator, Callable
from typing import Any

import pytest

from custom_components.plc_bridge.plc import ConnectionConfig, TlsMode
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient
from simulators.tecomat import DEFAULT_PASSWORD, DEFAULT_USER, TecomatSimulator

type ConfigFactory = Callable[..., ConnectionConfig]


@pytest.fixture
async def tecomat_sim() -> AsyncGenerator[TecomatSimulator]:
    """A Tecomat simulator on 127.0.0.1: plain HTTP, digest, no benchmark variables."""
    sim = TecomatSimulator(bench=0)
    await sim.start()
    yield sim
    await sim.stop()


@pytest.fixture
def tecomat_config(tecomat_sim: TecomatSimulator) -> ConfigFactory:
    """Make the settings of a client of the simulator (Prague clock); changes override."""

    def make(**changes: Any) -> ConnectionConfig:
        settings: dict[str, Any] = {
            "host": tecomat_sim.host,
            "port": tecomat_sim.port,
            "username": DEFAULT_USER,
            "password": DEFAULT_PASSWORD,
            "tls": TlsMode.NONE,
            "timeout": 5.0,
            "time_zone": "Europe/Prague",
        }
        return ConnectionConfig(**(settings | changes))

    return make


@pytest.fixture
async def tecomat_client(tecomat_config: ConfigFactory) -> AsyncGenerator[TecomatClient]:
    """A client connected to the simulator (its own HTTP session), closed afterwards."""
    client = TecomatClient(tecomat_config())
    await client.connect()
    yield client
    await client.close()
