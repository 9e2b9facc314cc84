"""LOGO! fixtures, imported by tests/plc/test_logo_*.py: a LOGO! of each generation, its client."""

from __future__ import annotations

from collections.abc import AsyncGenerator

import pytest

from custom_components.plc_bridge.plc.vendors.logo import LogoClient
from custom_components.plc_bridge.plc.vendors.logo.options import DEFAULT_TSAPS
from simulators.logo import LogoSimulator
from tests.loopback import ConfigFactory, config_factory, connected, running

GENERATIONS = ("0ba7", "0ba8", "8_x")


@pytest.fixture(params=GENERATIONS)
async def logo_sim(request: pytest.FixtureRequest) -> AsyncGenerator[LogoSimulator]:
    """A LOGO! of each generation, answering its default server TSAP, on a free loopback port."""
    async with running(LogoSimulator(request.param)) as sim:
        yield sim


@pytest.fixture
def logo_config(logo_sim: LogoSimulator) -> ConfigFactory:
    """Make the settings of a client of the simulator: its generation, the default TSAPs."""
    local, remote = DEFAULT_TSAPS[logo_sim.generation]
    options = {"generation": logo_sim.generation, "local_tsap": local, "remote_tsap": remote}
    return config_factory(logo_sim, timeout=2.0, options=options)


@pytest.fixture
async def logo_client(logo_config: ConfigFactory) -> AsyncGenerator[LogoClient]:
    """A client connected to the simulator, closed afterwards."""
    async with connected(LogoClient(logo_config())) as client:
        yield client
