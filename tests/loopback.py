"""Simulators on loopback and clients of them: how every fixture of both layers starts and stops.

A vendor's fixtures say only what is its own (the simulator's switches, the client's settings);
starting, stopping, connecting and closing are done here, once.
"""

from __future__ import annotations

from collections.abc import AsyncIterator, Callable
from contextlib import asynccontextmanager
from typing import Any, Protocol

from custom_components.plc_bridge.plc import ConnectionConfig, PlcClient

type ConfigFactory = Callable[..., ConnectionConfig]
"""Makes the settings of a client of a simulator; keyword arguments override them."""


class Server(Protocol):
    """A simulator (or any loopback server) that a test starts and stops."""

    host: str
    port: int

    async def start(self) -> None:
        """Listen on a free loopback port."""

    async def stop(self) -> None:
        """Stop listening."""


@asynccontextmanager
async def running[S: Server](sim: S) -> AsyncIterator[S]:
    """Start a simulator on a free loopback port; stop it afterwards, whatever happened."""
    await sim.start()
    try:
        yield sim
    finally:
        await sim.stop()


@asynccontextmanager
async def connected[C: PlcClient](client: C) -> AsyncIterator[C]:
    """Connect a client; close it afterwards (its own HTTP session with it)."""
    await client.connect()
    try:
        yield client
    finally:
        await client.close()


def config_factory(sim: Server, **settings: Any) -> ConfigFactory:
    """Return a maker of the settings of a client of `sim`: its address, its certificate's pin.

    `settings` are the vendor's; the maker's own keyword arguments override both. The pin is
    read when the settings are made, so a test that gives the simulator a new certificate
    gets the new pin.
    """

    def make(**changes: Any) -> ConnectionConfig:
        fingerprint = getattr(sim, "fingerprint", None) or ""
        base: dict[str, Any] = {"host": sim.host, "port": sim.port, "fingerprint": fingerprint}
        return ConnectionConfig(**(base | settings | changes))

    return make
