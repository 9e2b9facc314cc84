"""Time from entry setup to every state written, for 1,000 points in 10 devices.

Run by `scripts/bench` (pytest with the test suite's fixtures), on the current Home Assistant:
the S7-200 SMART simulator holds 1,000 word points spread over 10 device subentries of one PLC.
"""

from __future__ import annotations

import json
import time

from homeassistant.const import STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.helpers import device_registry as dr

from simulators.s7_smart import S7SmartSimulator
from tests.entries import plant_entry

DEVICES = 10
PER_DEVICE = 100


def wall() -> float:
    """Seconds of a clock the test's frozen time leaves alone (freezegun patches the others)."""
    return time.clock_gettime(time.CLOCK_MONOTONIC_RAW)


async def test_setup_time(hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator) -> None:
    """Set the PLC up; every point's state written and available; print the figures.

    The fixture freezes the clock (the clients pace by it), so the time is taken from another.
    """
    entry = plant_entry(hass, s7_smart_ha_sim, DEVICES, PER_DEVICE)
    started = wall()
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    elapsed = wall() - started
    states = [s for s in hass.states.async_all("sensor") if s.entity_id.startswith("sensor.mach")]
    available = sum(state.state != STATE_UNAVAILABLE for state in states)
    devices = len(dr.async_entries_for_config_entry(dr.async_get(hass), entry.entry_id))
    result = {
        "check": "setup_time",
        "vendor": "s7_smart",
        "points": DEVICES * PER_DEVICE,
        "devices": devices,
        "states_written": len(states),
        "available": available,
        "setup_to_states_ms": round(elapsed * 1000),
        "requests_first_poll": entry.runtime_data.client.metrics.last_poll_requests,
    }
    print("\nBENCH " + json.dumps(result))
    assert available == DEVICES * PER_DEVICE
    assert devices == DEVICES + 1
