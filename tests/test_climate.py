"""Tests of climate entities built from several points, against the S7-200 SMART simulator."""

from __future__ import annotations

from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.climate import (
    ATTR_CURRENT_TEMPERATURE,
    ATTR_HVAC_ACTION,
    ATTR_HVAC_MODE,
    ATTR_HVAC_MODES,
    ATTR_MAX_TEMP,
    ATTR_MIN_TEMP,
    ATTR_PRESET_MODE,
    ATTR_PRESET_MODES,
    ATTR_TARGET_TEMP_STEP,
    DOMAIN as CLIMATE_DOMAIN,
    SERVICE_SET_HVAC_MODE,
    SERVICE_SET_PRESET_MODE,
    SERVICE_SET_TEMPERATURE,
    SERVICE_TURN_ON,
)
from homeassistant.const import ATTR_ENTITY_ID, ATTR_TEMPERATURE, STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import ServiceValidationError
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from simulators.s7_smart import S7SmartSimulator
from tests.entries import make_entry, point, poll

pytestmark = pytest.mark.no_pacing

MODES = "0=off;1=heat;2=cool;3=auto"
BOILER = [
    point(
        "c1",
        "Boiler",
        "climate",
        "VW50",
        "signed",
        role="current_temperature",
        scale=0.1,
        read_only=True,
    ),
    point(
        "c2",
        "Boiler",
        "climate",
        "VW52",
        "signed",
        role="target_temperature",
        scale=0.1,
        min=5.0,
        max=30.0,
        step=0.5,
    ),
    point("c3", "Boiler", "climate", "VW54", "signed", role="hvac_mode", value_map=MODES),
    point(
        "c4",
        "Boiler",
        "climate",
        "VW56",
        "signed",
        role="hvac_action",
        value_map="0=idle;1=heating",
        read_only=True,
    ),
]
ON_OFF = point("c5", "Boiler", "climate", "Q0.7", "signed", role="on_off")
BOILER_ID = "climate.s7_200_smart_boiler"


@pytest.fixture
def boiler_sim(s7_smart_ha_sim: S7SmartSimulator) -> S7SmartSimulator:
    """The simulator holding a boiler at 21.5 °C, set to 20 °C, heating."""
    for address, value in (("VW50", 215), ("VW52", 200), ("VW54", 1), ("VW56", 1)):
        s7_smart_ha_sim.set(address, value)
    return s7_smart_ha_sim


async def set_up(hass: HomeAssistant, sim: S7SmartSimulator, points: list[Any]) -> MockConfigEntry:
    """Set up the simulator's entry with these points."""
    entry = make_entry(hass, sim, points)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    return entry


async def climate(hass: HomeAssistant, service: str, **data: Any) -> None:
    """Call a climate action on the boiler."""
    await hass.services.async_call(
        CLIMATE_DOMAIN, service, {ATTR_ENTITY_ID: BOILER_ID, **data}, blocking=True
    )


async def test_boiler(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, boiler_sim: S7SmartSimulator
) -> None:
    """Temperatures scaled, mode and action mapped; writes go back through the conversions."""
    await set_up(hass, boiler_sim, BOILER)
    state = hass.states.get(BOILER_ID)
    assert state.state == "heat"
    assert state.attributes[ATTR_CURRENT_TEMPERATURE] == 21.5
    assert state.attributes[ATTR_TEMPERATURE] == 20
    assert state.attributes[ATTR_HVAC_ACTION] == "heating"
    assert state.attributes[ATTR_HVAC_MODES] == ["off", "heat", "cool", "auto"]
    assert (state.attributes[ATTR_MIN_TEMP], state.attributes[ATTR_MAX_TEMP]) == (5, 30)
    assert state.attributes[ATTR_TARGET_TEMP_STEP] == 0.5
    await climate(hass, SERVICE_SET_TEMPERATURE, **{ATTR_TEMPERATURE: 22.5})
    assert boiler_sim.get("VW52") == 225
    await climate(hass, SERVICE_SET_HVAC_MODE, **{ATTR_HVAC_MODE: "cool"})
    assert boiler_sim.get("VW54") == 2
    boiler_sim.set("VW56", 0)
    await poll(hass, freezer)
    state = hass.states.get(BOILER_ID)
    assert (state.state, state.attributes[ATTR_HVAC_ACTION]) == ("cool", "idle")


async def test_out_of_range_refused(hass: HomeAssistant, boiler_sim: S7SmartSimulator) -> None:
    """A target outside min..max is refused before anything is sent."""
    await set_up(hass, boiler_sim, BOILER)
    with pytest.raises(ServiceValidationError):
        await climate(hass, SERVICE_SET_TEMPERATURE, **{ATTR_TEMPERATURE: 40})
    assert boiler_sim.calls["write"] == 0


async def test_on_off_part(hass: HomeAssistant, boiler_sim: S7SmartSimulator) -> None:
    """Off is written to the on/off part (the mode is kept); on writes it back."""
    boiler_sim.set("Q0.7", True)
    await set_up(hass, boiler_sim, [*BOILER, ON_OFF])
    await climate(hass, SERVICE_SET_HVAC_MODE, **{ATTR_HVAC_MODE: "off"})
    assert boiler_sim.get("Q0.7") is False
    assert boiler_sim.get("VW54") == 1
    assert hass.states.get(BOILER_ID).state == "off"
    await climate(hass, SERVICE_TURN_ON)
    assert boiler_sim.get("Q0.7") is True
    assert hass.states.get(BOILER_ID).state == "heat"


async def test_failing_part_alone(hass: HomeAssistant, boiler_sim: S7SmartSimulator) -> None:
    """A part at a bad address shows as unknown while the others show."""
    points = [
        point("c1", "Boiler", "climate", "VW30000", "signed", role="current_temperature"),
        *BOILER[1:],
    ]
    await set_up(hass, boiler_sim, points)
    state = hass.states.get(BOILER_ID)
    assert state.state == "heat"
    assert state.attributes[ATTR_CURRENT_TEMPERATURE] is None
    assert state.attributes[ATTR_TEMPERATURE] == 20


async def test_unavailable_when_no_part_reads(
    hass: HomeAssistant, boiler_sim: S7SmartSimulator
) -> None:
    """A climate entity none of whose parts reads is unavailable."""
    bad = point("c1", "Boiler", "climate", "VW30000", "signed", role="current_temperature")
    await set_up(hass, boiler_sim, [bad])
    assert hass.states.get(BOILER_ID).state == STATE_UNAVAILABLE


async def test_refused_write(hass: HomeAssistant, boiler_sim: S7SmartSimulator) -> None:
    """A mode written to a read-only part is refused before anything is sent."""
    mode = ("c3", {**BOILER[2][1], "read_only": True})
    await set_up(hass, boiler_sim, [*BOILER[:2], mode, BOILER[3]])
    with pytest.raises(ServiceValidationError) as err:
        await climate(hass, SERVICE_SET_HVAC_MODE, **{ATTR_HVAC_MODE: "auto"})
    assert err.value.translation_key == "read_only"
    assert boiler_sim.calls["write"] == 0


async def test_no_request_of_its_own(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, boiler_sim: S7SmartSimulator
) -> None:
    """A climate, a cover, a select and an alarm word: still one read request per poll."""
    points = [
        *BOILER,
        point("s1", "Shutter", "cover", "VW40", "signed", role="position", read_only=True),
        point("s2", "Shutter", "cover", "Q0.4", "signed", role="open"),
        point("mode", "Mode", "select", "VW30", "signed", value_map="0=Off;1=Auto"),
        point("alarms", "Alarms", "event", "VW70", "signed", bits="0=Overheat"),
    ]
    await set_up(hass, boiler_sim, points)
    reads = boiler_sim.calls["read"]
    await poll(hass, freezer, 3)
    assert boiler_sim.calls["read"] == reads + 3


async def test_preset_map(hass: HomeAssistant, boiler_sim: S7SmartSimulator) -> None:
    """Presets are the labels of the preset part's map, written by their codes."""
    boiler_sim.set("VW58", 1)
    preset = point(
        "c6", "Boiler", "climate", "VW58", "signed", role="preset", value_map="0=Comfort;1=Eco"
    )
    await set_up(hass, boiler_sim, [*BOILER, preset])
    state = hass.states.get(BOILER_ID)
    assert (state.attributes[ATTR_PRESET_MODE], state.attributes[ATTR_PRESET_MODES]) == (
        "Eco",
        ["Comfort", "Eco"],
    )
    await climate(hass, SERVICE_SET_PRESET_MODE, **{ATTR_PRESET_MODE: "Comfort"})
    assert boiler_sim.get("VW58") == 0
