"""S7 actions and diagnostics: multi-point writes, reads, the CPU clock, what diagnostics show."""

from __future__ import annotations

from datetime import datetime, timedelta
from zoneinfo import ZoneInfo

from freezegun.api import FrozenDateTimeFactory
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import HomeAssistantError, ServiceValidationError
from homeassistant.util import dt as dt_util
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from pytest_homeassistant_custom_component.components.diagnostics import (
    get_diagnostics_for_config_entry,
)
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from simulators.s7 import S7Simulator
from tests.entries import call, poll
from tests.harness import SimFactory, make_s7_entry, spread


async def test_write_two_points_one_request(
    hass: HomeAssistant, s7_ha_sim: S7Simulator, s7_setup: MockConfigEntry
) -> None:
    """Two points of different areas go in one multi-variable write request."""
    writes, requests = s7_ha_sim.calls["write"], s7_ha_sim.requests
    points = [
        {"address": "db1.dbd12", "data_type": "REAL", "value": 1.25},
        {"address": "M11.7", "data_type": "BOOL", "value": True},
    ]
    await call(hass, "write", s7_setup, points=points)
    assert s7_ha_sim.calls["write"] - writes == 1
    assert s7_ha_sim.get_db(1, 12, 4) == bytes.fromhex("3fa00000")
    assert s7_ha_sim.get_bytes("M", 11, 1) == b"\x80"
    # The write, then the refresh it asks for (its planned reads).
    client = s7_setup.runtime_data.client
    planned = client.requests_for(list(s7_setup.runtime_data.coordinator.data.values))
    assert s7_ha_sim.requests - requests == 1 + planned


async def test_write_checked_before_sending(
    hass: HomeAssistant, s7_ha_sim: S7Simulator, s7_setup: MockConfigEntry
) -> None:
    """An INT out of range refuses the whole action before anything reaches the CPU."""
    points = [
        {"address": "DB1.DBW2", "data_type": "INT", "value": 5},
        {"address": "DB1.DBW4", "data_type": "INT", "value": 40000},
    ]
    with pytest.raises(ServiceValidationError):
        await call(hass, "write", s7_setup, points=points)
    assert s7_ha_sim.calls["write"] == 0
    assert s7_ha_sim.get_db(1, 2, 2) == (1234).to_bytes(2, "big")


@pytest.mark.parametrize("day", ["1989-12-31", "2169-01-01T12:00:00+01:00"])
async def test_date_checked_before_sending(
    hass: HomeAssistant, s7_ha_sim: S7Simulator, s7_setup: MockConfigEntry, day: str
) -> None:
    """A DATE outside 1990..2168 is refused by the action's check, before any write."""
    points = [{"address": "DB1.DBW4", "data_type": "DATE", "value": day}]
    with pytest.raises(ServiceValidationError, match="a DATE runs from 1990-01-01"):
        await call(hass, "write", s7_setup, points=points)
    assert s7_ha_sim.calls["write"] == 0


async def test_read(hass: HomeAssistant, s7_ha_sim: S7Simulator, s7_setup: MockConfigEntry) -> None:
    """The read action answers each point; one outside its DB fails alone."""
    s7_ha_sim.set_db(1, 20, bytes([20, 2]) + b"OK")
    response = await call(
        hass,
        "read",
        s7_setup,
        points=[
            {"address": "DB1.DBD8", "data_type": "REAL"},
            {"address": "DB1.DBB20", "data_type": "STRING[20]"},
            {"address": "DB1.DBW2000", "data_type": "INT"},
        ],
    )
    assert response is not None
    assert response["values"] == {"DB1.DBD8": 21.5, "DB1.DBB20": "OK", "DB1.DBW2000": None}
    assert set(response["errors"]) == {"DB1.DBW2000"}


async def test_sync_clock(
    hass: HomeAssistant, s7_ha_sim: S7Simulator, s7_setup: MockConfigEntry
) -> None:
    """sync_clock sets the CPU clock to Home Assistant's time, in the PLC's (HA's) zone."""
    s7_ha_sim.clock = datetime(2001, 2, 3, 4, 5, 6)
    clocks = s7_ha_sim.calls["clock"]
    await call(hass, "sync_clock", s7_setup)
    await hass.async_block_till_done()
    local = dt_util.now().astimezone(ZoneInfo(hass.config.time_zone)).replace(tzinfo=None)
    assert s7_ha_sim.calls["clock"] == clocks + 2  # set, then read again by the refresh
    assert abs(s7_ha_sim.clock - local) < timedelta(seconds=1)
    shown = s7_setup.runtime_data.coordinator.data.status.clock
    assert shown is not None
    assert abs(shown.replace(tzinfo=None) - local) < timedelta(seconds=1)


async def test_sync_clock_refused(
    hass: HomeAssistant, s7_ha_sim: S7Simulator, s7_setup: MockConfigEntry
) -> None:
    """A protected CPU refuses the clock: the action fails, the clock stays."""
    s7_ha_sim.clock = datetime(2001, 2, 3, 4, 5, 6)
    s7_ha_sim.write_protected = True
    with pytest.raises(HomeAssistantError, match="refused to set its clock"):
        await call(hass, "sync_clock", s7_setup)
    assert s7_ha_sim.clock.year == 2001


async def test_diagnostics(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    s7_ha_sim: S7Simulator,
    s7_setup: MockConfigEntry,
) -> None:
    """Diagnostics show the S7 settings, the CPU, values and the plan; not where it is."""
    result = await get_diagnostics_for_config_entry(hass, hass_client, s7_setup)
    data = result["entry"]["data"]
    assert data["vendor"] == "s7"
    assert data["host"] == "**REDACTED**"
    assert data["vendor_options"] == {"connection": "rack_slot", "rack": 0, "slot": 1}
    device = result["device"]
    assert device["serial"] == "**REDACTED**"
    assert device["model"] == "CPU 315-2 PN/DP"
    assert device["extra"]["pdu_size"] == "480"
    assert device["extra"]["remote_tsap"] == "01.01"
    assert result["status"]["mode"] == "RUN"
    assert result["results"]["DB1.DBD8|REAL"] == {"ok": True, "value": 21.5}
    assert result["results"]["DB1.DBX0.0|BOOL"] == {"ok": True, "value": True}
    assert result["poll"]["planned_requests"] == s7_setup.runtime_data.client.requests_for(
        list(s7_setup.runtime_data.coordinator.data.values), 480
    )
    assert result["poll"]["last_update_success"] is True
    text = str(result)
    assert "127.0.0.1" not in text
    assert S7Simulator.serial not in text


async def test_diagnostics_plan_for_negotiated_pdu(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    s7_ha_sims: SimFactory,
    freezer: FrozenDateTimeFactory,
) -> None:
    """The planned requests diagnostics show are the ones a poll costs on this CPU (PDU 960)."""
    sim = await s7_ha_sims(pdu_size=960, dbs={1: 512, 2: 512, 3: 512})
    entry = make_s7_entry(hass, sim, spread(30))
    assert await hass.config_entries.async_setup(entry.entry_id)
    before = sim.requests
    await poll(hass, freezer)
    result = await get_diagnostics_for_config_entry(hass, hass_client, entry)
    assert result["poll"]["planned_requests"] == sim.requests - before == 1
