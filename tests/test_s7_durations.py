"""S7 durations in Home Assistant: TIME and S5TIME show as duration sensors, set as seconds."""

from __future__ import annotations

import struct

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.number import ATTR_VALUE, SERVICE_SET_VALUE
from homeassistant.const import ATTR_DEVICE_CLASS, ATTR_ENTITY_ID, ATTR_UNIT_OF_MEASUREMENT
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import HomeAssistantError
import pytest

from custom_components.plc_bridge.model.points import suggested_platform
from custom_components.plc_bridge.plc.vendors.s7 import S7Client
from simulators.s7 import S7Simulator
from tests.entries import call, point, poll
from tests.harness import SimFactory, make_s7_entry

POINTS = [
    point("runtime", "Runtime", "sensor", "DB1.DBD0", "TIME", read_only=True),
    point("delay", "Delay", "number", "DB1.DBW4", "S5TIME"),
    point("day_start", "Day start", "sensor", "DB1.DBD6", "TOD", read_only=True),
]
RUNTIME = "sensor.s7_300_runtime"
DELAY = "number.s7_300_delay"
DAY_START = "sensor.s7_300_day_start"


async def test_durations(
    hass: HomeAssistant, s7_ha_sims: SimFactory, freezer: FrozenDateTimeFactory
) -> None:
    """A TIME is a duration sensor in seconds; an S5TIME number writes seconds, refused if off."""
    sim: S7Simulator = await s7_ha_sims()
    sim.set_db(1, 0, struct.pack(">i", 90_500))  # T#1M_30S_500MS
    sim.set_db(1, 4, b"\x11\x20")  # S5T#12S: 120 x 100 ms
    sim.set_db(1, 6, struct.pack(">I", 6 * 3_600_000))  # TOD#06:00:00
    entry = make_s7_entry(hass, sim, POINTS)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()

    runtime = hass.states.get(RUNTIME)
    assert runtime.state == "90.5"
    assert runtime.attributes[ATTR_DEVICE_CLASS] == "duration"
    assert runtime.attributes[ATTR_UNIT_OF_MEASUREMENT] == "s"
    assert hass.states.get(DAY_START).state == "21600.0"
    delay = hass.states.get(DELAY)
    assert delay.state == "12.0"
    assert delay.attributes[ATTR_DEVICE_CLASS] == "duration"

    await hass.services.async_call(
        "number", SERVICE_SET_VALUE, {ATTR_ENTITY_ID: DELAY, ATTR_VALUE: 1.5}, blocking=True
    )
    assert sim.get_db(1, 4, 2) == b"\x01\x50"  # 150 x 10 ms
    with pytest.raises(HomeAssistantError):
        await hass.services.async_call(
            "number", SERVICE_SET_VALUE, {ATTR_ENTITY_ID: DELAY, ATTR_VALUE: 9991}, blocking=True
        )
    assert sim.get_db(1, 4, 2) == b"\x01\x50"

    sim.set_db(1, 0, struct.pack(">i", -250))
    await poll(hass, freezer)
    assert hass.states.get(RUNTIME).state == "-0.25"

    # The read action answers JSON: a duration in seconds.
    points = [
        {"address": "DB1.DBD0", "data_type": "TIME"},
        {"address": "T1", "data_type": "S5TIME"},
    ]
    response = await call(hass, "read", entry, points=points)
    assert response is not None
    assert response["values"] == {"DB1.DBD0": -0.25, "T1": 0.0}


def test_suggested_platforms() -> None:
    """A writable duration is a number, a read-only one a sensor."""
    assert suggested_platform(S7Client, "DB1.DBD0", "TIME") == "number"
    assert suggested_platform(S7Client, "DB1.DBD0", "TIME", read_only=True) == "sensor"
    assert suggested_platform(S7Client, "IW0", "S5TIME") == "sensor"


async def test_duration_as_text(hass: HomeAssistant, s7_ha_sims: SimFactory) -> None:
    """A TIME as text shows hh:mm:ss.zzz and takes it back, as the write action does."""
    sim: S7Simulator = await s7_ha_sims()
    sim.set_db(1, 0, struct.pack(">i", 90_500))
    entry = make_s7_entry(hass, sim, [point("timer", "Timer", "text", "DB1.DBD0", "TIME")])
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert hass.states.get("text.s7_300_timer").state == "00:01:30.500"
    await hass.services.async_call(
        "text",
        "set_value",
        {ATTR_ENTITY_ID: "text.s7_300_timer", ATTR_VALUE: "01:00:00.250"},
        blocking=True,
    )
    assert sim.get_db(1, 0, 4) == struct.pack(">i", 3_600_250)
    points = [{"address": "DB1.DBD8", "data_type": "TOD", "value": "06:30:00"}]
    await call(hass, "write", entry, points=points)
    assert sim.get_db(1, 8, 4) == struct.pack(">I", 23_400_000)
