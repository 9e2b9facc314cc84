"""Home Assistant fixtures for the PLCnext vendor: its simulator and an entry of it."""

from __future__ import annotations

from collections.abc import AsyncGenerator, Iterable
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.core import HomeAssistant
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from simulators.plcnext import DEFAULT_PASSWORD, DEFAULT_USER, PlcnextSimulator
from tests.ha_fixtures import (
    PointData,
    add_entry,
    entry_data,
    point,
    serving,
    set_up,
    unload_all,
)

PLCNEXT_ENTRY_ID = "01JPLCBR1DGE00000000PLCNEXT"

PLCNEXT_POINTS = [  # full paths, as the point form stores them
    point(
        "temperature",
        "Temperature",
        "sensor",
        "Arp.Plc.Eclr/MainInstance.Temperature",
        "REAL",
        unit_of_measurement="°C",
        device_class="temperature",
        state_class="measurement",
        read_only=True,
    ),
    point(
        "setpoint",
        "Setpoint",
        "number",
        "Arp.Plc.Eclr/MainInstance.Setpoint",
        "REAL",
        min=10.0,
        max=30.0,
    ),
    point("pump", "Pump", "switch", "Arp.Plc.Eclr/MainInstance.Pump", "BOOL"),
    point("alarm", "Alarm", "binary_sensor", "Arp.Plc.Eclr/MainInstance.Alarm", "BOOL"),
    point("level", "Level 2", "sensor", "Arp.Plc.Eclr/MainInstance.Levels[2]", "INT"),
    point("message", "Message", "text", "Arp.Plc.Eclr/MainInstance.Message", "STRING"),
]


def plcnext_data(sim: PlcnextSimulator, **changes: Any) -> dict[str, Any]:
    """Return entry data for the simulator: pinned certificate, default user, a clock variable."""
    clock = {"clock_variable": "Arp.Plc.Eclr/MainInstance.Clock"}
    credentials = (DEFAULT_USER, DEFAULT_PASSWORD)
    return entry_data("plcnext", sim, credentials, "pin", clock) | changes


def make_plcnext_entry(
    hass: HomeAssistant,
    sim: PlcnextSimulator,
    points: Iterable[PointData] = PLCNEXT_POINTS,
    **changes: Any,
) -> MockConfigEntry:
    """Add an entry of the simulator with the given points (not set up yet)."""
    return add_entry(
        hass,
        title="PLCnext",
        entry_id=PLCNEXT_ENTRY_ID,
        unique_id=f"{sim.host}:{sim.port}",
        data=plcnext_data(sim, **changes),
        points=points,
    )


@pytest.fixture
async def plcnext_sim(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory
) -> AsyncGenerator[PlcnextSimulator]:
    """A started PLCnext simulator (HTTPS, user authentication on); time frozen meanwhile."""
    async with serving(hass, PlcnextSimulator()) as sim:
        yield sim


@pytest.fixture
async def plcnext_entry(
    hass: HomeAssistant, plcnext_sim: PlcnextSimulator
) -> AsyncGenerator[MockConfigEntry]:
    """The simulator's entry with PLCNEXT_POINTS, set up (unloaded afterwards)."""
    yield await set_up(hass, make_plcnext_entry(hass, plcnext_sim))
    await unload_all(hass)
