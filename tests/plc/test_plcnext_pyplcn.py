"""pyPLCn 1.0.3 (PyPI), an independent PLCnext REST client, against the simulator.

So that the simulator is not shaped by our own client alone: pyPLCn opens a session before it
logs in, sends the two login steps as JSON without a content type, registers a group with a
JSON body and a `pathPrefix`, polls it as `/groups/<id>/?sessionID=…&` from a thread, and
writes values as lower-case text (`"true"`, `"23.5"`) to `/variables/`, all under
`https://<ip>:443/_pxc_api/v1.2/`. Its port is fixed at 443: the simulator listens there on
127.0.0.1 where it may, else the requests are sent to its own port (only the TCP port changes).
"""

from __future__ import annotations

import asyncio
from collections.abc import AsyncGenerator, Callable
import logging
import time
from typing import Any

import pytest
import requests
from requests.adapters import HTTPAdapter

from simulators.plcnext import DEFAULT_PASSWORD, DEFAULT_USER, PlcnextSimulator

pytestmark = [
    pytest.mark.filterwarnings("ignore:setDaemon:DeprecationWarning"),  # pyPLCn's thread
    pytest.mark.filterwarnings("ignore::urllib3.exceptions.InsecureRequestWarning"),  # verify=False
]
PYPLCN_PORT = 443
VARIABLES = [
    "MainInstance.Temperature",
    "MainInstance.Pump",
    "MainInstance.Levels[2]",
    "MainInstance.Recipe.Weight",
    "MainInstance.Counter",
]


class _ToPort(HTTPAdapter):
    """Send pyPLCn's requests for 127.0.0.1:443 to the simulator's port instead."""

    def __init__(self, port: int) -> None:
        """Remember the simulator's port."""
        super().__init__()
        self._port = port

    def send(self, request: requests.PreparedRequest, **kwargs: Any) -> requests.Response:  # type: ignore[override]
        """Rewrite the port, send."""
        assert request.url is not None
        request.url = request.url.replace(":443/", f":{self._port}/", 1)
        return super().send(request, **kwargs)


def _peer_class() -> Any:
    """Import pyPLCn, keeping its import-time logging.basicConfig off the test run's logging."""
    root = logging.getLogger()
    handlers, level = list(root.handlers), root.level
    try:
        from pyPLCn import pyPLCn
    finally:
        root.handlers[:] = handlers
        root.setLevel(level)
    return pyPLCn


@pytest.fixture(params=[True, False], ids=["user", "no-user"])
async def peer_sim(request: pytest.FixtureRequest) -> AsyncGenerator[PlcnextSimulator]:
    """A simulator (user authentication on or off) on 127.0.0.1:443 where it may be."""
    sim = PlcnextSimulator(auth=request.param)
    try:
        await sim.start(port=PYPLCN_PORT)
    except OSError:  # not root, or 443 taken: any port, and pyPLCn's requests redirected
        await sim.start()
    yield sim
    await sim.stop()


@pytest.fixture
async def peer(peer_sim: PlcnextSimulator) -> AsyncGenerator[Any]:
    """A pyPLCn client of the simulator, connected, its poll thread running every 20 ms."""
    client = _peer_class()()
    client.set_timeout(5)
    if peer_sim.port != PYPLCN_PORT:
        client.s.mount(f"https://{peer_sim.host}:{PYPLCN_PORT}/", _ToPort(peer_sim.port))
    client.set_var_names(list(VARIABLES))
    user, password = (DEFAULT_USER, DEFAULT_PASSWORD) if peer_sim.auth else ("", "")
    await asyncio.to_thread(client.connect, peer_sim.host, user, password, 20)
    yield client
    client.close()
    await asyncio.to_thread(client._worker_thread.join, 5)
    assert not client._worker_thread.is_alive()


async def until(check: Callable[[], bool], timeout: float = 5.0) -> None:
    """Wait for pyPLCn's poll thread to make the check true."""
    end = time.monotonic() + timeout
    while not check():
        assert time.monotonic() < end, "pyPLCn did not get there in time"
        await asyncio.sleep(0.02)


async def test_reads_a_group(peer_sim: PlcnextSimulator, peer: Any) -> None:
    """pyPLCn registers one group after its session (and login) and polls it; values match."""
    await until(lambda: len(peer.read_vars) == len(VARIABLES))
    assert peer.is_connected(), peer.last_error
    assert {name: peer.get_var(name) for name in VARIABLES} == {
        "MainInstance.Temperature": 21.5,
        "MainInstance.Pump": False,
        "MainInstance.Levels[2]": 20,
        "MainInstance.Recipe.Weight": 2.5,
        "MainInstance.Counter": 799244562,
    }
    assert len(peer_sim.groups) == 1
    assert peer_sim.access.logins == (1 if peer_sim.auth else 0)
    assert len(peer_sim.access.sessions) == 1
    peer_sim.set("MainInstance.Counter", 7)
    await until(lambda: peer.get_var("MainInstance.Counter") == 7)


async def test_writes_values_as_text(peer_sim: PlcnextSimulator, peer: Any) -> None:
    """pyPLCn's text values ("true", "23.5", "-7") are taken, and its poll shows them."""
    await until(lambda: len(peer.read_vars) == len(VARIABLES))
    for name, value in (("MainInstance.Pump", True), ("MainInstance.Setpoint", 23.5)):
        await asyncio.to_thread(peer.set_var, name, value)
        assert peer._status_code == 200, peer.last_error
    await asyncio.to_thread(peer.set_var, "MainInstance.Speed", -7)
    assert peer_sim.get("MainInstance.Pump") is True
    assert peer_sim.get("MainInstance.Setpoint") == 23.5
    assert peer_sim.get("MainInstance.Speed") == -7
    await until(lambda: peer.get_var("MainInstance.Pump") is True)
    assert peer.is_connected()
