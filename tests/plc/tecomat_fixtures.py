"""Tecomat fixtures for the protocol tests: a TecoApi simulator and clients of it."""

from __future__ import annotations

from collections.abc import AsyncGenerator

import pytest

from custom_components.plc_bridge.plc import TlsMode
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient
from simulators.tecomat import DEFAULT_PASSWORD, DEFAULT_USER, TecomatSimulator
from tests.loopback import ConfigFactory, config_factory, connected, running

__all__ = ["ConfigFactory", "basic_sim", "tecomat_client", "tecomat_config", "tecomat_sim"]


@pytest.fixture
async def tecomat_sim() -> AsyncGenerator[TecomatSimulator]:
    """A Tecomat simulator on 127.0.0.1: plain HTTP, digest, no benchmark variables."""
    async with running(TecomatSimulator(bench=0)) as sim:
        yield sim


@pytest.fixture
async def basic_sim() -> AsyncGenerator[TecomatSimulator]:
    """A Tecomat simulator taking Basic authentication over plain HTTP (also for HA tests)."""
    async with running(TecomatSimulator(auth="basic", bench=0)) as sim:
        yield sim


@pytest.fixture
def tecomat_config(tecomat_sim: TecomatSimulator) -> ConfigFactory:
    """Make the settings of a client of the simulator (Prague clock); changes override."""
    return config_factory(
        tecomat_sim,
        username=DEFAULT_USER,
        password=DEFAULT_PASSWORD,
        tls=TlsMode.NONE,
        timeout=5.0,
        time_zone="Europe/Prague",
    )


@pytest.fixture
async def tecomat_client(tecomat_config: ConfigFactory) -> AsyncGenerator[TecomatClient]:
    """A client connected to the simulator (its own HTTP session), closed afterwards."""
    async with connected(TecomatClient(tecomat_config())) as client:
        yield client
