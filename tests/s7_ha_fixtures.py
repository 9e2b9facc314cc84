"""Home Assistant fixtures for the S7 (ISO-on-TCP) vendor: a simulated CPU and its entry.

Registered for every test through `pytest_plugins` in tests/conftest.py. The names start with
`s7_ha_`/`s7_` beside the protocol tests' `s7_sim` so the two sets never shadow each other.
"""

from __future__ import annotations

from collections.abc import AsyncGenerator, Awaitable, Callable, Iterable
from contextlib import AsyncExitStack
import threading
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.core import HomeAssistant
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.plc.vendors.s7 import S7Client
from simulators.s7 import S7Simulator
from tests.loopback import running

from .ha_fixtures import PointData, add_entry, entry_data, point, set_up, unload_all

S7_ENTRY_ID = "01JPLCBR1DGE00000000S7TEST"
S7_TITLE = "S7-300"
RACK_SLOT = {"connection": "rack_slot", "rack": 0, "slot": 1}

SNAP7_THREADS = ("(_server_loop)", "(_handle_client)")  # python-snap7's server thread targets

type SimFactory = Callable[..., Awaitable[S7Simulator]]

S7_POINTS = [
    point(
        "temperature",
        "Temperature",
        "sensor",
        "DB1.DBD8",
        "REAL",
        unit_of_measurement="°C",
        device_class="temperature",
        state_class="measurement",
    ),
    point("level", "Level", "sensor", "DB1.DBW2", "INT"),
    point("counter", "Counter", "sensor", "MW20", "INT"),
    point("door", "Door", "binary_sensor", "DB1.DBX0.0", "BOOL", device_class="door"),
    point("pump", "Pump", "switch", "M10.1", "BOOL"),
    point("setpoint", "Setpoint", "number", "DB1.DBW4", "INT", min=0.0, max=100.0, step=1.0),
]
"""DB and M points of every platform the tests use (entity ids: `<platform>.s7_300_<name>`)."""


def s7_data(sim: S7Simulator, **options: Any) -> dict[str, Any]:
    """Return the entry data the config flow stores for the simulator (rack 0, slot 1)."""
    return entry_data("s7", sim, ("", ""), options=RACK_SLOT | options)


def make_s7_entry(
    hass: HomeAssistant,
    sim: S7Simulator,
    points: Iterable[PointData] = S7_POINTS,
    **options: Any,
) -> MockConfigEntry:
    """Add an entry of the simulator with the given points (not set up yet)."""
    return add_entry(
        hass,
        title=S7_TITLE,
        entry_id=S7_ENTRY_ID,
        unique_id=S7Simulator.serial,
        data=s7_data(sim, **options),
        points=points,
    )


def spread(count: int) -> list[PointData]:
    """Return `count` REAL sensors over DB1..DB3, 34 bytes apart: the PDU decides the packing."""
    return [
        point(
            f"p{index}",
            f"Point {index}",
            "sensor",
            f"DB{1 + index % 3}.DBD{index // 3 * 34}",
            "REAL",
        )
        for index in range(count)
    ]


def fill(sim: S7Simulator) -> None:
    """Put the values of S7_POINTS into the simulator."""
    sim.set_db(1, 0, b"\x01")  # DB1.DBX0.0 on
    sim.set_db(1, 2, (1234).to_bytes(2, "big"))
    sim.set_db(1, 4, (40).to_bytes(2, "big"))
    sim.set_db(1, 8, bytes.fromhex("41ac0000"))  # 21.5
    sim.set_bytes("M", 20, (-7).to_bytes(2, "big", signed=True))


@pytest.fixture
async def s7_ha_sims(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory
) -> AsyncGenerator[SimFactory]:
    """Start S7 simulators built as a test asks; afterwards unload, stop, check no thread stays.

    Time is frozen (the client's reconnect backoff runs on the monotonic clock the freezer moves).
    """
    async with AsyncExitStack() as running_sims:

        async def make(**settings: Any) -> S7Simulator:
            return await running_sims.enter_async_context(running(S7Simulator(**settings)))

        yield make
        await unload_all(hass)
    lingering = [t.name for t in threading.enumerate() if t.name.endswith(SNAP7_THREADS)]
    assert not lingering, f"snap7 server threads left running: {lingering}"


@pytest.fixture
async def s7_ha_sim(s7_ha_sims: SimFactory) -> S7Simulator:
    """An S7-300-like CPU (rack 0, slot 1, PDU 480, DB1 of 1024 bytes) holding S7_POINTS."""
    sim = await s7_ha_sims()
    fill(sim)
    return sim


@pytest.fixture
def s7_entry(hass: HomeAssistant, s7_ha_sim: S7Simulator) -> MockConfigEntry:
    """The simulator's entry (rack/slot), with S7_POINTS."""
    return make_s7_entry(hass, s7_ha_sim)


@pytest.fixture
async def s7_setup(hass: HomeAssistant, s7_entry: MockConfigEntry) -> MockConfigEntry:
    """The simulator's entry, set up (unloaded by `s7_ha_sims`)."""
    return await set_up(hass, s7_entry)


@pytest.fixture
def s7_fast_reconnect(monkeypatch: pytest.MonkeyPatch) -> None:
    """Keep the reconnect backoff below one poll interval (first 1 s, longest 5 s)."""
    monkeypatch.setattr(S7Client, "reconnect_delay", (1.0, 5.0))
