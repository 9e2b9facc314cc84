"""Tests of valves and fans built from several points, against the S7-200 SMART simulator."""

from __future__ import annotations

from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.fan import (  # type: ignore[attr-defined]
    ATTR_PERCENTAGE,
    ATTR_PRESET_MODE,
    ATTR_PRESET_MODES,
    DOMAIN as FAN_DOMAIN,
    SERVICE_SET_PERCENTAGE,
    SERVICE_SET_PRESET_MODE,
)
from homeassistant.components.valve import (  # type: ignore[attr-defined]
    ATTR_CURRENT_POSITION,
    ATTR_POSITION,
    DOMAIN as VALVE_DOMAIN,
    SERVICE_SET_VALVE_POSITION,
)
from homeassistant.const import (
    ATTR_ENTITY_ID,
    SERVICE_CLOSE_VALVE,
    SERVICE_OPEN_VALVE,
    SERVICE_TURN_ON,
    STATE_OFF,
    STATE_ON,
)
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import ServiceValidationError
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from simulators.s7_smart import S7SmartSimulator
from tests.entries import make_entry, point, poll

pytestmark = pytest.mark.no_pacing

RANGE = {"raw_min": 0, "raw_max": 27648, "shown_min": 0, "shown_max": 100}
POINTS = [
    point("v1", "Mixer", "valve", "VW80", "signed", role="position", read_only=True, **RANGE),
    point("v2", "Mixer", "valve", "VW82", "signed", role="set_position", **RANGE),
    point("w1", "Inlet", "valve", "Q1.0", "signed", role="open"),
    point("w2", "Inlet", "valve", "Q1.1", "signed", role="close"),
    point("w3", "Inlet", "valve", "I1.0", "signed", role="closed_limit", read_only=True),
    point("f1", "Vent", "fan", "I1.1", "signed", role="state", read_only=True),
    point("f2", "Vent", "fan", "M3.0", "signed", role="command"),
    point("f3", "Vent", "fan", "VW84", "signed", role="percentage"),
    point("f4", "Vent", "fan", "VW86", "signed", role="preset", value_map="0=Low;1=High"),
]


@pytest.fixture
async def valves_and_fan(hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator) -> MockConfigEntry:
    """The simulator's entry with two valves and a fan, set up."""
    s7_smart_ha_sim.set("VW80", 6912)
    s7_smart_ha_sim.set("I1.0", True)
    s7_smart_ha_sim.set("VW84", 30)
    s7_smart_ha_sim.set("VW86", 1)
    entry = make_entry(hass, s7_smart_ha_sim, POINTS)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    return entry


async def act(hass: HomeAssistant, domain: str, service: str, name: str, **data: Any) -> None:
    """Call an action on an entity of the test PLC."""
    await hass.services.async_call(
        domain, service, {ATTR_ENTITY_ID: f"{domain}.s7_200_smart_{name}", **data}, blocking=True
    )


async def test_valves(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    s7_smart_ha_sim: S7SmartSimulator,
    valves_and_fan: MockConfigEntry,
) -> None:
    """A valve with a position; a valve with open and close commands and a closed limit."""
    mixer = hass.states.get("valve.s7_200_smart_mixer")
    assert (mixer.state, mixer.attributes[ATTR_CURRENT_POSITION]) == ("open", 25)
    await act(hass, VALVE_DOMAIN, SERVICE_SET_VALVE_POSITION, "mixer", **{ATTR_POSITION: 50})
    assert s7_smart_ha_sim.get("VW82") == 13824
    assert hass.states.get("valve.s7_200_smart_inlet").state == "closed"
    await act(hass, VALVE_DOMAIN, SERVICE_OPEN_VALVE, "inlet")
    assert s7_smart_ha_sim.get("Q1.0") is True
    await act(hass, VALVE_DOMAIN, SERVICE_CLOSE_VALVE, "inlet")
    assert s7_smart_ha_sim.get("Q1.1") is True
    s7_smart_ha_sim.set("I1.0", False)
    await poll(hass, freezer)
    assert hass.states.get("valve.s7_200_smart_inlet").state == "open"


async def test_fan(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    s7_smart_ha_sim: S7SmartSimulator,
    valves_and_fan: MockConfigEntry,
) -> None:
    """On and off by command, state read back, speed and presets written."""
    vent = hass.states.get("fan.s7_200_smart_vent")
    assert vent.state == STATE_OFF
    assert (vent.attributes[ATTR_PERCENTAGE], vent.attributes[ATTR_PRESET_MODE]) == (30, "High")
    assert vent.attributes[ATTR_PRESET_MODES] == ["Low", "High"]
    await act(hass, FAN_DOMAIN, SERVICE_TURN_ON, "vent", **{ATTR_PERCENTAGE: 60})
    assert (s7_smart_ha_sim.get("M3.0"), s7_smart_ha_sim.get("VW84")) == (True, 60)
    await act(hass, FAN_DOMAIN, SERVICE_SET_PRESET_MODE, "vent", **{ATTR_PRESET_MODE: "Low"})
    assert s7_smart_ha_sim.get("VW86") == 0
    await act(hass, FAN_DOMAIN, SERVICE_SET_PERCENTAGE, "vent", **{ATTR_PERCENTAGE: 0})
    assert s7_smart_ha_sim.get("M3.0") is False
    s7_smart_ha_sim.set("I1.1", True)
    await poll(hass, freezer)
    assert hass.states.get("fan.s7_200_smart_vent").state == STATE_ON
    with pytest.raises(ServiceValidationError):
        await act(hass, FAN_DOMAIN, SERVICE_SET_PRESET_MODE, "vent", **{ATTR_PRESET_MODE: "Max"})


async def test_own_device_class(hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator) -> None:
    """The device class the entity's page stores on its parts is the valve's and the cover's;
    a limit switch's own class of another kind (opening) is not taken for it."""
    points = [
        point("w1", "Inlet", "valve", "Q1.0", "signed", role="open", device_class="water"),
        point("w2", "Inlet", "valve", "Q1.1", "signed", role="close", device_class="water"),
        point("c1", "Gate", "cover", "Q1.2", "signed", role="open", device_class="garage"),
        point(
            "c2",
            "Hatch",
            "cover",
            "I1.0",
            "signed",
            role="closed_limit",
            read_only=True,
            device_class="opening",
        ),
    ]
    entry = make_entry(hass, s7_smart_ha_sim, points)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert hass.states.get("valve.s7_200_smart_inlet").attributes["device_class"] == "water"
    assert hass.states.get("cover.s7_200_smart_gate").attributes["device_class"] == "garage"
    assert "device_class" not in hass.states.get("cover.s7_200_smart_hatch").attributes
