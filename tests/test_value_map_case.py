"""A value map naming Home Assistant's states takes them in any case (`Open`, `OPEN`), and stores
them as Home Assistant spells them; every door (form, table) goes through the same check."""

from __future__ import annotations

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.climate import ATTR_HVAC_MODES
from homeassistant.core import HomeAssistant
import pytest

from custom_components.plc_bridge.model.composite import part_data
from custom_components.plc_bridge.model.conversion import spelled_as_states
from custom_components.plc_bridge.model.point_table import parse_points
from custom_components.plc_bridge.plc.vendors import client_class
from simulators.s7_smart import S7SmartSimulator
from tests.entries import make_entry, point, poll
from tests.model.test_composite import TABLE

pytestmark = pytest.mark.no_pacing

SMART = client_class("s7_smart")


def test_spelled_as_states() -> None:
    """Labels naming a state in another case take its spelling; others stay as typed."""
    states = {"open", "closed", "heat_cool"}
    assert (
        spelled_as_states("0=Closed; 2=OPEN;3=Heat_Cool", states) == "0=closed;2=open;3=heat_cool"
    )
    assert spelled_as_states("0=Shut;1=open", states) == "0=Shut;1=open"
    assert spelled_as_states("no pair", states) == "no pair"


@pytest.mark.parametrize(
    ("role", "platform", "typed", "stored"),
    [
        (
            "status",
            "cover",
            "0=CLOSED;1=Opening;2=Open;3=closing",
            "0=closed;1=opening;2=open;3=closing",
        ),
        ("hvac_mode", "climate", "0=Off;1=HEAT;2=Cool", "0=off;1=heat;2=cool"),
        ("hvac_action", "climate", "0=Idle;1=Heating", "0=idle;1=heating"),
    ],
)
def test_any_case_taken_and_stored_as_home_assistant_spells_it(
    role: str, platform: str, typed: str, stored: str
) -> None:
    """The form's check takes the states in any case and stores Home Assistant's spelling."""
    values = {
        "name": "Part",
        "platform": platform,
        "role": role,
        "address": "VW50",
        "data_type": "signed",
        "value_map": typed,
    }
    data, errors, _ = part_data(SMART, values)
    assert errors == {}
    assert data["value_map"] == stored


def test_a_label_naming_no_state_still_refused() -> None:
    """Case aside, a label that is no state of Home Assistant is refused as before."""
    values = {
        "name": "Boiler",
        "platform": "climate",
        "role": "hvac_mode",
        "address": "VW50",
        "data_type": "signed",
        "value_map": "0=OFF;1=Warm",
    }
    assert part_data(SMART, values)[1] == {"value_map": "role_labels"}


def test_table_takes_any_case() -> None:
    """An imported table's map in another case is taken, spelled as Home Assistant spells it."""
    row = "Gate,VW58,signed,cover,status,0=CLOSED;1=Opening;2=Open;3=Closing,,,,,,,,,,\n"
    points, errors = parse_points(SMART, TABLE + row)
    assert errors == []
    (status,) = [data for data in points if data["name"] == "Gate"]
    assert status["value_map"] == "0=closed;1=opening;2=open;3=closing"


async def test_climate_of_a_map_typed_in_capitals(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, freezer: FrozenDateTimeFactory
) -> None:
    """A climate whose mode map was typed `0=Off;1=HEAT` shows and sets Home Assistant's modes."""
    typed = {
        "name": "Boiler",
        "platform": "climate",
        "role": "hvac_mode",
        "address": "VW50",
        "data_type": "signed",
        "value_map": "0=Off;1=HEAT",
    }
    data, errors, _ = part_data(SMART, typed)
    assert errors == {}
    current = point("c1", "Boiler", "climate", "VD100", "float", role="current_temperature")
    entry = make_entry(hass, s7_smart_ha_sim, [current, ("c2", data)])
    s7_smart_ha_sim.set("VW50", 1)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await poll(hass, freezer)
    state = hass.states.get("climate.s7_200_smart_boiler")
    assert state is not None
    assert (state.state, state.attributes[ATTR_HVAC_MODES]) == ("heat", ["off", "heat"])
