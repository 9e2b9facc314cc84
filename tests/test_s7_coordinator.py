"""S7 polling: planned requests per poll, the CPU state, a lost and regained connection."""

from __future__ import annotations

import logging

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import ConfigEntryState
from homeassistant.const import STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.model.points import entry_points
from custom_components.plc_bridge.plc.vendors.s7 import S7Client
from simulators.s7 import S7Simulator
from tests.entries import poll
from tests.harness import SimFactory, make_s7_entry, spread

TEMPERATURE = "sensor.s7_300_temperature"
MODE = "sensor.s7_300_operating_mode"
PUMP = "switch.s7_300_pump"


@pytest.mark.parametrize(("pdu_size", "expected"), [(240, 2), (480, 1), (960, 1)])
async def test_requests_per_poll_as_planned(
    hass: HomeAssistant,
    s7_ha_sims: SimFactory,
    freezer: FrozenDateTimeFactory,
    pdu_size: int,
    expected: int,
) -> None:
    """30 points cost what the client plans for the negotiated PDU, counted at the CPU."""
    sim = await s7_ha_sims(pdu_size=pdu_size, dbs={1: 512, 2: 512, 3: 512})
    entry = make_s7_entry(hass, sim, spread(30))
    assert await hass.config_entries.async_setup(entry.entry_id)
    client = entry.runtime_data.client
    assert isinstance(client, S7Client)
    assert client.pdu_size == pdu_size
    planned = client.requests_for(
        [config.point for config in entry_points(entry).values()], client.pdu_size
    )
    assert planned == expected  # the reads; the CPU state and clock once a minute
    before = sim.requests
    await poll(hass, freezer)
    assert sim.requests - before == planned
    assert sim.calls["szl"] >= 1
    assert client.metrics.last_poll_requests == planned
    values = [s.state for s in hass.states.async_all("sensor") if "point_" in s.entity_id]
    assert values == ["0.0"] * 30


async def test_cpu_state(
    hass: HomeAssistant,
    s7_ha_sim: S7Simulator,
    s7_setup: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """The operating mode sensor follows the CPU's RUN/STOP switch (SZL 0x0424), read with the
    clock once a minute: not a request at every poll."""
    state = hass.states.get(MODE)
    assert state.state == "run"
    assert state.attributes["options"][:2] == ["run", "stop"]
    s7_ha_sim.cpu_state = "STOP"
    szl = s7_ha_sim.calls["szl"]
    await poll(hass, freezer, times=5)  # 50 s
    assert s7_ha_sim.calls["szl"] == szl
    assert hass.states.get(MODE).state == "run"
    await poll(hass, freezer)  # 60 s
    assert s7_ha_sim.calls["szl"] == szl + 1
    assert hass.states.get(MODE).state == "stop"
    assert hass.states.get(TEMPERATURE).state == "21.5"  # memory stays readable in STOP
    s7_ha_sim.cpu_state = "RUN"
    await poll(hass, freezer, times=6)
    assert hass.states.get(MODE).state == "run"


async def test_no_state_without_szl(hass: HomeAssistant, s7_ha_sims: SimFactory) -> None:
    """A CPU without SZL (S7-200, LOGO!) still sets up; it gets no operating mode sensor."""
    sim = await s7_ha_sims(szl=False)
    entry = make_s7_entry(hass, sim)
    assert await hass.config_entries.async_setup(entry.entry_id)
    assert entry.state is ConfigEntryState.LOADED
    assert hass.states.get(MODE) is None
    assert hass.states.get(TEMPERATURE).state == "0.0"


async def test_connection_lost_and_back(
    hass: HomeAssistant,
    s7_ha_sim: S7Simulator,
    s7_setup: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """Stopped CPU: entities unavailable, one warning for many polls; restarted: values back."""
    caplog.set_level(logging.DEBUG, logger="custom_components.plc_bridge")
    await s7_ha_sim.stop()
    await poll(hass, freezer, times=6)
    for entity_id in (TEMPERATURE, MODE, PUMP):
        assert hass.states.get(entity_id).state == STATE_UNAVAILABLE
    lost = [r for r in caplog.records if "Lost connection to S7 PLC" in r.getMessage()]
    assert len(lost) == 1
    assert lost[0].levelno == logging.WARNING
    loud = [
        r
        for r in caplog.records
        if r.levelno >= logging.WARNING and r.name.startswith("custom_components.plc_bridge")
    ]
    assert len(loud) <= 2  # the session's warning, and the coordinator's one error

    attempts = [r for r in caplog.records if "still unreachable" in r.getMessage()]
    assert len(attempts) == 5  # polls 2..6 tried once each: waits 1, 2, 4, 8, 9 s < 10 s

    s7_ha_sim.set_db(1, 8, bytes.fromhex("41b40000"))  # 22.5
    connections = s7_ha_sim.connections
    await s7_ha_sim.restart()
    # The backoff is capped below the poll interval: the first poll after the restart reconnects.
    await poll(hass, freezer)
    assert hass.states.get(TEMPERATURE).state == "22.5"
    assert hass.states.get(MODE).state == "run"
    assert hass.states.get(PUMP).state == "off"
    assert s7_ha_sim.connections == connections + 1
    restored = [r for r in caplog.records if "restored" in r.getMessage()]
    assert len(restored) == 1
    assert len([r for r in caplog.records if "Lost connection" in r.getMessage()]) == 1


async def test_cable_pulled(
    hass: HomeAssistant,
    s7_ha_sim: S7Simulator,
    s7_setup: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Dropped connections while the CPU keeps listening: one failed poll, then back."""
    connections = s7_ha_sim.connections
    s7_ha_sim.drop_clients()
    await poll(hass, freezer)
    await poll(hass, freezer)
    assert hass.states.get(TEMPERATURE).state == "21.5"
    assert s7_ha_sim.connections == connections + 1


async def test_setup_retried_when_unreachable(hass: HomeAssistant, s7_ha_sims: SimFactory) -> None:
    """A CPU that refuses the slot (or is away) leaves the entry to retry, not failed."""
    sim = await s7_ha_sims(slot=2)
    entry = make_s7_entry(hass, sim)  # slot 1
    assert not await hass.config_entries.async_setup(entry.entry_id)
    assert entry.state is ConfigEntryState.SETUP_RETRY
    assert sim.connections == 0
