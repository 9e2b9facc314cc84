"""TecoApi and PLCnext durations in Home Assistant: duration sensors, numbers set in seconds."""

from __future__ import annotations

from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.number import ATTR_VALUE, SERVICE_SET_VALUE
from homeassistant.components.text import SERVICE_SET_VALUE as SET_TEXT
from homeassistant.const import (
    ATTR_DEVICE_CLASS,
    ATTR_ENTITY_ID,
    ATTR_UNIT_OF_MEASUREMENT,
    STATE_UNAVAILABLE,
)
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import HomeAssistantError
import pytest

from custom_components.plc_bridge.model.points import point_data, suggested_platform
from custom_components.plc_bridge.plc.vendors.plcnext import PlcnextClient
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient
from simulators.plcnext import PlcnextSimulator
from simulators.tecomat import TecomatSimulator
from tests.entries import point, poll, set_up
from tests.harness import make_plcnext_entry, make_tecomat_entry

MAIN = "Arp.Plc.Eclr/MainInstance."


async def set_number(hass: HomeAssistant, entity_id: str, value: float) -> None:
    """Set a number entity, as the frontend does."""
    await hass.services.async_call(
        "number", SERVICE_SET_VALUE, {ATTR_ENTITY_ID: entity_id, ATTR_VALUE: value}, blocking=True
    )


async def test_tecomat_durations(
    hass: HomeAssistant, tecomat_ha_sim: TecomatSimulator, freezer: FrozenDateTimeFactory
) -> None:
    """TIME a number of seconds, TOD a duration sensor, a TIME text as hh:mm:ss.zzz."""
    points = [
        point("runtime", "Runtime", "number", "plcData.varTime", "TIME"),
        point("start", "Start", "sensor", "plcData.varTod", "TOD", read_only=True),
        point("clock", "Clock", "text", "plcData.varTime", "TIME"),
        point("int", "Int", "sensor", "plcData.varInt", "INT"),
    ]
    await set_up(hass, make_tecomat_entry(hass, tecomat_ha_sim, points))
    runtime = hass.states.get("number.fx2_cp2080_runtime")
    assert runtime.state == "432123.45"
    assert runtime.attributes[ATTR_DEVICE_CLASS] == "duration"
    assert runtime.attributes[ATTR_UNIT_OF_MEASUREMENT] == "s"
    start = hass.states.get("sensor.fx2_cp2080_start")
    assert (start.state, start.attributes[ATTR_DEVICE_CLASS]) == ("27000.0", "duration")
    assert hass.states.get("text.fx2_cp2080_clock").state == "120:02:03.450"

    await set_number(hass, "number.fx2_cp2080_runtime", 90.5)
    assert tecomat_ha_sim.get("plcData.varTime") == 90_500
    assert hass.states.get("text.fx2_cp2080_clock").state == "00:01:30.500"
    await hass.services.async_call(
        "text",
        SET_TEXT,
        {ATTR_ENTITY_ID: "text.fx2_cp2080_clock", ATTR_VALUE: "1:00:00"},
        blocking=True,
    )
    assert tecomat_ha_sim.get("plcData.varTime") == 3_600_000
    before = tecomat_ha_sim.requests
    with pytest.raises(HomeAssistantError, match="a TIME holds 0"):
        await set_number(hass, "number.fx2_cp2080_runtime", 2_147_484)  # past 24d20:31:23.647
    with pytest.raises(HomeAssistantError):
        await hass.services.async_call(
            "text",
            SET_TEXT,
            {ATTR_ENTITY_ID: "text.fx2_cp2080_clock", ATTR_VALUE: "soon"},
            blocking=True,
        )
    assert tecomat_ha_sim.requests == before  # refused before anything is sent
    assert tecomat_ha_sim.get("plcData.varTime") == 3_600_000

    tecomat_ha_sim.rewrite = lambda body: body.replace(b'"07:30:00.000"', b'"7h"')
    await poll(hass, freezer)
    assert hass.states.get("sensor.fx2_cp2080_start").state == STATE_UNAVAILABLE
    assert hass.states.get("number.fx2_cp2080_runtime").state == "3600.0"
    assert hass.states.get("sensor.fx2_cp2080_int").state == "-2222"


async def test_plcnext_durations(
    hass: HomeAssistant, plcnext_ha_sim: PlcnextSimulator, freezer: FrozenDateTimeFactory
) -> None:
    """TIME and LTIME as durations: seconds, or the time unit the point names."""
    points = [
        point("runtime", "Runtime", "number", MAIN + "Runtime", "TIME"),
        point(
            "runtime_ms",
            "Runtime ms",
            "number",
            MAIN + "Runtime",
            "TIME",
            **{"unit_of_measurement": "ms"},
        ),
        point("uptime", "Uptime", "sensor", MAIN + "Uptime", "LTIME", read_only=True),
        point("speed", "Speed", "sensor", MAIN + "Speed", "INT"),
    ]
    await set_up(hass, make_plcnext_entry(hass, plcnext_ha_sim, points))
    assert hass.states.get("number.plcnext_runtime").state == "90.0"
    runtime_ms = hass.states.get("number.plcnext_runtime_ms")
    assert runtime_ms.state == "90000"
    assert runtime_ms.attributes[ATTR_UNIT_OF_MEASUREMENT] == "ms"
    uptime = hass.states.get("sensor.plcnext_uptime")
    assert uptime.state == "5.0"
    assert uptime.attributes[ATTR_DEVICE_CLASS] == "duration"

    await set_number(hass, "number.plcnext_runtime", 1.5)
    assert plcnext_ha_sim.get(MAIN + "Runtime") == 1_500
    await set_number(hass, "number.plcnext_runtime_ms", 250)
    assert plcnext_ha_sim.get(MAIN + "Runtime") == 250
    before = plcnext_ha_sim.requests
    with pytest.raises(HomeAssistantError, match=r"a TIME holds -2147483\.648"):
        await set_number(hass, "number.plcnext_runtime", -2_147_484)
    assert plcnext_ha_sim.requests == before
    assert plcnext_ha_sim.get(MAIN + "Runtime") == 250

    plcnext_ha_sim.set(MAIN + "Runtime", "soon")
    plcnext_ha_sim.set(MAIN + "Uptime", 7_000_000_001)  # ns: shown to the microsecond
    await poll(hass, freezer)
    assert hass.states.get("number.plcnext_runtime").state == STATE_UNAVAILABLE
    assert hass.states.get("sensor.plcnext_uptime").state == "7.0"
    assert hass.states.get("sensor.plcnext_speed").state == "-1200"


@pytest.mark.parametrize(
    ("values", "errors"),
    [
        ({"platform": "sensor", "unit_of_measurement": "min"}, {}),
        ({"platform": "sensor", "as_text": True}, {}),
        ({"platform": "number", "unit_of_measurement": "ms"}, {}),
        ({"platform": "text"}, {}),
        (
            {"platform": "number", "unit_of_measurement": "kg"},
            {"unit_of_measurement": "unit_not_valid"},
        ),
        ({"platform": "switch"}, {"platform": "needs_bool"}),
    ],
)
def test_point_form(values: dict[str, Any], errors: dict[str, str]) -> None:
    """A duration takes a time unit, text mode on a sensor, or the text platform."""
    base = {"name": "Runtime", "address": "plcData.varTime", "data_type": "TIME"}
    data, found, _ = point_data(TecomatClient, base | values)
    assert found == errors
    if not errors and values.get("as_text"):
        assert data["as_text"] is True


def test_suggested_platforms() -> None:
    """A writable duration is a number, a read-only one a sensor."""
    assert suggested_platform(PlcnextClient, "MainInstance.Runtime", "TIME") == "number"
    assert suggested_platform(TecomatClient, "plcData.varTod", "TOD", read_only=True) == "sensor"
