"""Home Assistant fixtures for the SoftPLC WEB.TLM vendor: its simulator and an entry of it.

Registered for every test through `pytest_plugins` in tests/conftest.py.
"""

from __future__ import annotations

from collections.abc import AsyncGenerator, Iterable
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.core import HomeAssistant
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from simulators.softplc import SoftplcSimulator
from tests.ha_fixtures import PointData, add_entry, entry_data, point, serving

SOFTPLC_ENTRY_ID = "01JPLCBR1DGE00000000SOFTPLC"

SOFTPLC_POINTS = [
    point("temperature", "Temperature", "sensor", "F8:0", "REAL", read_only=True),
    point("count", "Count", "sensor", "N7:5", "INT"),
    point("preset", "Preset", "number", "T4:0.PRE", "INT", min=0.0, max=10000.0, step=1.0),
    point("lamp", "Lamp", "switch", "B3:0/2", "BOOL"),
    point("input", "Input", "binary_sensor", "I:0/0", "BOOL"),
    point("tag", "Important", "sensor", "important_int", "INT"),
]
"""Points of every type: a float, a word, a timer word, bits, a tag."""


def softplc_data(sim: SoftplcSimulator, **changes: Any) -> dict[str, Any]:
    """Return entry data for the simulator (plain HTTP unless it speaks TLS: then pinned)."""
    return entry_data("softplc", sim, None, "pin" if sim.tls else "none") | changes


def make_softplc_entry(
    hass: HomeAssistant,
    sim: SoftplcSimulator,
    points: Iterable[PointData] = SOFTPLC_POINTS,
    **changes: Any,
) -> MockConfigEntry:
    """Add an entry of the simulator with the given points (not set up yet)."""
    return add_entry(
        hass,
        title="SoftPLC",
        entry_id=SOFTPLC_ENTRY_ID,
        unique_id=f"{sim.host}:{sim.port}",
        data=softplc_data(sim, **changes),
        points=points,
    )


@pytest.fixture
async def softplc_sim(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory
) -> AsyncGenerator[SoftplcSimulator]:
    """A started SoftPLC simulator over HTTPS that takes PUTs only with a client certificate."""
    async with serving(hass, SoftplcSimulator(tls=True, put_auth=True)) as sim:
        yield sim


@pytest.fixture
async def softplc_http_sim(hass: HomeAssistant) -> AsyncGenerator[SoftplcSimulator]:
    """A started SoftPLC simulator over plain HTTP, without PUT authentication."""
    async with serving(hass, SoftplcSimulator(bench=0)) as sim:
        yield sim


def pem_pair(sim: SoftplcSimulator, *, trusted: bool = True) -> dict[str, str]:
    """Return the vendor options (as a form takes them) of a client certificate and its key."""
    certificate, key = sim.client_certificate(trusted=trusted)
    return {"client_certificate": certificate, "client_key": key}
