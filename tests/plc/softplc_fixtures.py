"""SoftPLC fixtures for the protocol tests: a WEB.TLM simulator and clients of it."""

from __future__ import annotations

from collections.abc import AsyncGenerator, Callable
from typing import Any

import pytest

from custom_components.plc_bridge.plc import ConnectionConfig, TlsMode
from custom_components.plc_bridge.plc.vendors.softplc import SoftplcClient
from simulators.softplc import SoftplcSimulator

type ConfigFactory = Callable[..., ConnectionConfig]


@pytest.fixture
async def softplc_sim() -> AsyncGenerator[SoftplcSimulator]:
    """A SoftPLC simulator on 127.0.0.1: plain HTTP, addresses echoed, no PUT authentication."""
    sim = SoftplcSimulator()
    await sim.start()
    yield sim
    await sim.stop()


@pytest.fixture
async def softplc_tls_sim() -> AsyncGenerator[SoftplcSimulator]:
    """A SoftPLC simulator over HTTPS that takes PUTs only with a client certificate."""
    sim = SoftplcSimulator(tls=True, put_auth=True)
    await sim.start()
    yield sim
    await sim.stop()


def softplc_config(sim: SoftplcSimulator, **changes: Any) -> ConnectionConfig:
    """Return the settings of a client of the simulator (pinned when it speaks TLS)."""
    settings: dict[str, Any] = {
        "host": sim.host,
        "port": sim.port,
        "tls": TlsMode.PIN if sim.tls else TlsMode.NONE,
        "fingerprint": sim.fingerprint or "",
        "timeout": 5.0,
    }
    return ConnectionConfig(**(settings | changes))


@pytest.fixture
def softplc_settings() -> Callable[..., ConnectionConfig]:
    """Return `softplc_config`, for tests that start simulators of their own."""
    return softplc_config


@pytest.fixture
async def softplc_client(softplc_sim: SoftplcSimulator) -> AsyncGenerator[SoftplcClient]:
    """A client connected to the plain simulator (its own HTTP session), closed afterwards."""
    client = SoftplcClient(softplc_config(softplc_sim))
    await client.connect()
    yield client
    await client.close()
