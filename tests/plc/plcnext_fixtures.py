"""PLCnext fixtures for the protocol tests: a REST interface simulator and clients of it."""

from __future__ import annotations

from collections.abc import AsyncGenerator
from typing import Any

import pytest

from custom_components.plc_bridge.plc import TlsMode
from custom_components.plc_bridge.plc.vendors.plcnext import PlcnextClient
from simulators.plcnext import DEFAULT_PASSWORD, DEFAULT_USER, PlcnextSimulator
from tests.loopback import ConfigFactory, config_factory, connected, running

__all__ = ["ConfigFactory", "plcnext_client", "plcnext_config", "plcnext_sim"]


@pytest.fixture(params=[False, True], ids=["documented", "foreign"])
async def plcnext_sim(request: pytest.FixtureRequest) -> AsyncGenerator[PlcnextSimulator]:
    """A PLCnext simulator on 127.0.0.1 (HTTPS, user authentication on), in both error modes.

    "foreign" answers what the sources leave open with other reasons and error shapes.
    """
    async with running(PlcnextSimulator(foreign=request.param)) as sim:
        yield sim


@pytest.fixture
def plcnext_config(plcnext_sim: PlcnextSimulator) -> ConfigFactory:
    """Make the settings of a client of the simulator: pinned certificate, Prague clock."""
    return config_factory(
        plcnext_sim,
        username=DEFAULT_USER,
        password=DEFAULT_PASSWORD,
        tls=TlsMode.PIN,
        timeout=5.0,
        time_zone="Europe/Prague",
        options={"clock_variable": "MainInstance.Clock"},
    )


@pytest.fixture
async def plcnext_client(plcnext_config: ConfigFactory) -> AsyncGenerator[PlcnextClient]:
    """A client connected to the simulator (its own HTTP session), closed afterwards."""
    async with connected(PlcnextClient(plcnext_config())) as client:
        yield client


SESSION_READINGS: dict[str, dict[str, Any]] = {
    "granted-equal": {},
    "granted-shorter": {"session_cap": 1.0},
    "absent-shorter": {"session_cap": 1.0, "session_answer": "absent"},
    "absent-equal": {"session_answer": "absent"},
}
"""Row 20 of simulators/plcnext/READINGS.md: the session timeout a PLC grants, and where it
says so (the create answer, or only the sessions report)."""


@pytest.fixture(params=list(SESSION_READINGS), ids=list(SESSION_READINGS))
async def plcnext_sessions(
    request: pytest.FixtureRequest,
) -> AsyncGenerator[tuple[PlcnextSimulator, ConfigFactory]]:
    """A simulator granting sessions as one reading of SESSION_READINGS, and its settings."""
    async with running(PlcnextSimulator()) as sim:
        for switch, value in SESSION_READINGS[request.param].items():
            assert hasattr(sim, switch), switch
            setattr(sim, switch, value)
        yield (
            sim,
            config_factory(
                sim, username=DEFAULT_USER, password=DEFAULT_PASSWORD, tls=TlsMode.PIN, timeout=5.0
            ),
        )
