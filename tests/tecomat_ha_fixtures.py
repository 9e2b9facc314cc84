"""Home Assistant fixtures for the TecoApi (tecomat) vendor: its simulator and an entry of it.

Registered for every test through `pytest_plugins` in tests/conftest.py.
"""

from __future__ import annotations

from collections.abc import AsyncGenerator, Iterable
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.core import HomeAssistant
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from simulators.tecomat import DEFAULT_PASSWORD, DEFAULT_USER, TecomatSimulator
from tests.ha_fixtures import (
    PointData,
    add_entry,
    entry_data,
    point,
    serving,
    set_up,
    unload_all,
)
from tests.plc.tecomat_fixtures import basic_sim  # noqa: F401  (one fixture, both layers)

TECOMAT_ENTRY_ID = "01JPLCBR1DGE00000000TECOMAT"
TECOMAT_SERIAL = "PP 0004"  # GetInfo's plc.serialNumber: the entry's unique id

TECOMAT_POINTS = [
    point(
        "inside",
        "Inside temperature",
        "sensor",
        "Main.myObject2.value",
        "REAL",
        unit_of_measurement="°C",
        device_class="temperature",
        state_class="measurement",
        read_only=True,
    ),
    point(
        "requested",
        "Requested temperature",
        "number",
        "Main.myObject3.value",
        "REAL",
        min=10.0,
        max=30.0,
        step=0.5,
    ),
    point("pump", "Circulation pump", "switch", "Main.pump.value", "BOOL"),
    point("bool1", "Bool 1", "binary_sensor", "plcData.varBool1", "BOOL"),
    point("int", "Int", "sensor", "plcData.varInt", "INT"),
    point("udint", "Salary", "sensor", "myObject.salary", "UDINT"),
    point("time", "Time", "sensor", "plcData.varTime", "TIME"),
    point("element", "Element", "sensor", "arr2[1][3]", "REAL"),
    point("greeting", "Greeting", "text", "plcData.varString", "STRING"),
    point("stamp", "Stamp", "datetime", "plcData.varDT", "DT"),
]
"""Points of several IEC types, chapter 5.3 objects, members and elements, every platform."""


def tecomat_data(sim: TecomatSimulator, **changes: Any) -> dict[str, Any]:
    """Return entry data for the simulator: plain HTTP, default user, Digest, a clock variable."""
    options = {"auth": sim.auth.method, "clock_variable": "setTime"}
    credentials = (DEFAULT_USER, DEFAULT_PASSWORD)
    return entry_data("tecomat", sim, credentials, options=options) | changes


def make_tecomat_entry(
    hass: HomeAssistant,
    sim: TecomatSimulator,
    points: Iterable[PointData] = TECOMAT_POINTS,
    **changes: Any,
) -> MockConfigEntry:
    """Add an entry of the simulator with the given points (not set up yet)."""
    return add_entry(
        hass,
        title="Fx2 CP2080",
        entry_id=TECOMAT_ENTRY_ID,
        unique_id=TECOMAT_SERIAL,
        data=tecomat_data(sim, **changes),
        points=points,
    )


@pytest.fixture
async def tecomat_sim(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory
) -> AsyncGenerator[TecomatSimulator]:
    """A started Tecomat simulator (Digest, plain HTTP, no benchmark variables).

    Time is frozen until every entry is unloaded, as for the S7-200 SMART fixture.
    """
    async with serving(hass, TecomatSimulator(bench=0)) as sim:
        yield sim


@pytest.fixture
async def tecomat_entry(
    hass: HomeAssistant, tecomat_sim: TecomatSimulator
) -> AsyncGenerator[MockConfigEntry]:
    """The simulator's entry with TECOMAT_POINTS, set up (unloaded afterwards)."""
    yield await set_up(hass, make_tecomat_entry(hass, tecomat_sim))
    await unload_all(hass)
