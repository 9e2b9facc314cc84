"""Picking points from the variables a loaded PLC publishes (TecoApi simulator)."""

from __future__ import annotations

from unittest.mock import AsyncMock

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import SOURCE_USER
from homeassistant.const import STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import CONF_POINTS, SUBENTRY_DEVICE
from custom_components.plc_bridge.plc import BrowseItem, PlcConnectionError
from simulators.tecomat import TecomatSimulator
from simulators.tecomat.values import Var
from tests.entries import read_edits
from tests.flows.forms import MACHINE, browse, error_message, listed, step
from tests.harness import make_tecomat_entry


async def test_pick_published_variables(
    hass: HomeAssistant, tecomat_entry: MockConfigEntry, freezer: FrozenDateTimeFactory
) -> None:
    """A filter by name or address; configured variables are not listed; picks become entities."""
    result = await browse(hass, tecomat_entry, "TEMPERATURE")
    assert result["step_id"] == "pick"
    # inside and requested temperature are points of the entry already
    # TecoApi declares no type: each offered one is guessed, and marked so
    assert listed(result) == {"outside temperature – Main.myObject1.value (REAL?)": "0"}
    result = await step(hass, result, {"variables": ["0"]})
    assert result["type"] is FlowResultType.MENU
    result = await step(hass, result, {"next_step_id": "browse"})
    result = await step(hass, result, {"filter": "plcData.varB"})
    labels = listed(result)
    assert "plcData.varBool0 (BOOL?)" in labels
    assert "plcData.varBool1 (BOOL?)" not in labels  # configured
    result = await step(hass, result, {"variables": [labels["plcData.varBool0 (BOOL?)"]]})
    result = await step(hass, result, {"next_step_id": "save"})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    (new,) = [s for s in tecomat_entry.subentries.values() if s.title == "Heating"]
    points = {data["address"]: data for data in new.data[CONF_POINTS].values()}
    assert points["Main.myObject1.value"]["platform"] == "sensor"
    assert points["Main.myObject1.value"]["unit_of_measurement"] == "°C"
    assert points["plcData.varBool0"]["platform"] == "switch"
    await hass.async_block_till_done()
    await read_edits(hass, freezer)
    entities = er.async_entries_for_config_entry(er.async_get(hass), tecomat_entry.entry_id)
    added = [e.entity_id for e in entities if e.config_subentry_id == new.subentry_id]
    assert len(added) == 2
    for entity_id in added:
        assert hass.states.get(entity_id).state != STATE_UNAVAILABLE, entity_id


async def test_long_lists_are_cut_and_browsed_once(
    hass: HomeAssistant, tecomat_entry: MockConfigEntry, monkeypatch: pytest.MonkeyPatch
) -> None:
    """301 matches list 50 (the form says so); a second filter asks the PLC nothing more."""
    items = [BrowseItem(address=f"big.v{i}", data_type="REAL") for i in range(301)]
    browsed = AsyncMock(return_value=items)
    monkeypatch.setattr(tecomat_entry.runtime_data.client, "browse", browsed)
    result = await browse(hass, tecomat_entry, "")
    assert result["step_id"] == "pick_first"
    assert result["description_placeholders"] | {"error": ""} == {
        "count": "301",
        "shown": "50",
        "error": "",
    }
    assert len(listed(result)) == 50
    menu = await step(hass, result, {})  # nothing ticked: back to the menu
    result = await step(hass, menu, {"next_step_id": "browse"})
    result = await step(hass, result, {"filter": "v30"})
    assert set(listed(result)) == {"big.v30 (REAL)", "big.v300 (REAL)"}
    assert browsed.await_count == 1


async def test_browse_failure_goes_back(
    hass: HomeAssistant, tecomat_entry: MockConfigEntry, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A PLC that cannot list its variables: the reason is shown, and the menu comes back."""
    browsed = AsyncMock(side_effect=PlcConnectionError("timed out"))
    monkeypatch.setattr(tecomat_entry.runtime_data.client, "browse", browsed)
    result = await browse(hass, tecomat_entry, "x")
    assert result["errors"] == {"base": "browse_failed"}
    assert "timed out" in error_message(result, "base", *MACHINE)
    menu = await step(hass, result, {})
    assert menu["type"] is FlowResultType.MENU


async def test_a_bad_pick_adds_nothing(
    hass: HomeAssistant, tecomat_entry: MockConfigEntry, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A variable the parser refuses is named; the others ticked with it are not added."""
    items = [
        BrowseItem(address="ok.v1", data_type="REAL"),
        BrowseItem(address="bad.v2", data_type="WSTRING"),
    ]
    monkeypatch.setattr(tecomat_entry.runtime_data.client, "browse", AsyncMock(return_value=items))
    result = await browse(hass, tecomat_entry, "v")
    result = await step(hass, result, {"variables": ["0", "1"]})
    assert result["errors"] == {"base": "pick_failed"}
    assert "- bad.v2: Invalid address" in error_message(result, "base", *MACHINE)
    menu = await step(hass, result, {"variables": ["0"]})
    assert menu["description_placeholders"]["count"] == "1"


@pytest.mark.usefixtures("tecomat_ha_sim")
async def test_no_pick_list_while_not_loaded(
    hass: HomeAssistant, tecomat_ha_sim: TecomatSimulator
) -> None:
    """Variables are listed only by a connected PLC: an entry not loaded offers no pick list."""
    entry = make_tecomat_entry(hass, tecomat_ha_sim)
    result = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_DEVICE), context={"source": SOURCE_USER}
    )
    menu = await step(hass, result, {"name": "Heating"})
    assert "browse" not in menu["menu_options"]
    assert "import_points" in menu["menu_options"]


async def test_variables_too_big_to_list_are_named(
    hass: HomeAssistant, tecomat_ha_sim: TecomatSimulator, tecomat_entry: MockConfigEntry
) -> None:
    """A structure the PLC cannot answer whole is said on a pick form it matches; arrays are
    listed. A list the filter keeps apart from it says nothing about it."""
    tecomat_ha_sim.variables["recipe"] = {f"step{i}": Var("INT", i) for i in range(200)}
    tecomat_ha_sim.variables["big"] = [Var("INT", i) for i in range(200)]
    result = await browse(hass, tecomat_entry, "big[19")
    assert not result["errors"]
    assert set(listed(result)) == {"big[19] (DINT?)", *(f"big[19{i}] (DINT?)" for i in range(10))}
    result = await browse(hass, tecomat_entry, "RECI")
    assert result["errors"] == {"base": "browse_unlisted"}
    assert error_message(result, "base", *MACHINE).startswith(
        "The PLC cannot list these variables here: recipe. "
    )
