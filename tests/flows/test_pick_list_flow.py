"""What the machine dialog shows: the pick list, the names of picked points, the menu, pickers."""

from __future__ import annotations

import re
from typing import Any
from unittest.mock import AsyncMock

from homeassistant.config_entries import SOURCE_USER
from homeassistant.core import HomeAssistant
from homeassistant.helpers.selector import SelectSelectorMode
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import CONF_POINTS, SUBENTRY_DEVICE
from custom_components.plc_bridge.plc import BrowseItem
from tests.flows.forms import STRINGS, translated

DEVICE = ("config_subentries", SUBENTRY_DEVICE)
STEPS = STRINGS["config_subentries"][SUBENTRY_DEVICE]["step"]
PUBLISHED = [
    BrowseItem(address="Arp.Plc.Eclr/plcData.varBool0", data_type="BOOL", name="plcData.varBool0"),
    BrowseItem(address="Boiler.temp", data_type="REAL"),
    BrowseItem(address="Main.obj.value", data_type="REAL", name="Outside temperature"),
    BrowseItem(address="Tank.temp", data_type="REAL"),
    BrowseItem(address="Main.fan.value", data_type="BOOL"),
]


async def step(hass: HomeAssistant, result: Any, values: dict[str, Any] | None = None) -> Any:
    """Submit a form or a menu choice; check its texts."""
    return translated(
        await hass.config_entries.subentries.async_configure(result["flow_id"], values or {}),
        *DEVICE,
    )


async def menu_of(hass: HomeAssistant, entry: MockConfigEntry, name: str = "Heating") -> Any:
    """Start a machine and return its menu."""
    result = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_DEVICE), context={"source": SOURCE_USER}
    )
    return await step(hass, result, {"name": name})


async def pick_form(
    hass: HomeAssistant, entry: MockConfigEntry, monkeypatch: pytest.MonkeyPatch, needle: str = ""
) -> Any:
    """Open the pick list of PUBLISHED with a filter."""
    monkeypatch.setattr(entry.runtime_data.client, "browse", AsyncMock(return_value=PUBLISHED))
    result = await step(hass, await menu_of(hass, entry), {"next_step_id": "browse"})
    return await step(hass, result, {"filter": needle})


def options(result: Any) -> list[dict[str, str]]:
    """Return the options of a form's one selector, in order."""
    (selector,) = result["data_schema"].schema.values()
    return list(selector.config["options"])


async def test_titled_variables_first_and_paths_said_once(
    hass: HomeAssistant, tecomat_entry: MockConfigEntry, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A variable the PLC gives a title is listed first; a name that is its path is not repeated."""
    result = await pick_form(hass, tecomat_entry, monkeypatch)
    assert [option["label"] for option in options(result)] == [
        "Outside temperature – Main.obj.value (REAL)",
        "Arp.Plc.Eclr/plcData.varBool0 (BOOL)",
        "Boiler.temp (REAL)",
        "Tank.temp (REAL)",
        "Main.fan.value (BOOL)",
    ]


async def test_a_whole_list_asks_no_narrower_filter(
    hass: HomeAssistant, tecomat_entry: MockConfigEntry, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Where every match is listed, the form does not ask for a narrower filter."""
    result = await pick_form(hass, tecomat_entry, monkeypatch)
    assert result["step_id"] == "pick"
    assert "narrower" not in STEPS["pick"]["description"]
    assert "narrower" in STEPS["pick_first"]["description"]


async def test_picked_points_get_readable_distinct_names(
    hass: HomeAssistant, tecomat_entry: MockConfigEntry, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Picks are named by title, else by their path's last parts, readable and told apart."""
    result = await pick_form(hass, tecomat_entry, monkeypatch)
    ticked = [option["value"] for option in options(result) if "Arp" not in option["label"]]
    result = await step(hass, result, {"variables": ticked})  # PLCnext's: test_plcnext_browse
    result = await step(hass, result, {"next_step_id": "save"})
    await hass.async_block_till_done()
    (machine,) = [s for s in tecomat_entry.subentries.values() if s.title == "Heating"]
    names = {data["address"]: data["name"] for data in machine.data[CONF_POINTS].values()}
    assert names == {
        "Main.obj.value": "Outside temperature",
        "Boiler.temp": "Boiler temp",
        "Tank.temp": "Tank temp",
        "Main.fan.value": "Fan",  # a TecoApi object's value is named after the object
    }


async def test_menu_keeps_save_in_view_in_a_stable_order(
    hass: HomeAssistant, tecomat_entry: MockConfigEntry
) -> None:
    """The menu lists five points by name and counts the rest; one point is not "1 points"."""
    menu = await menu_of(hass, tecomat_entry)
    table = "name,address,data_type\n" + "\n".join(f"W {i},w{i},INT" for i in range(12, 0, -1))
    result = await step(hass, menu, {"next_step_id": "import_points"})
    menu = await step(hass, result, {"table": table})
    assert menu["description_placeholders"]["points"].splitlines() == [
        *(f"- W {i} (sensor): w{i} (INT)" for i in range(1, 6)),
        "- … (+7)",
    ]
    assert menu["menu_options"][-1] == "save"
    assert not re.search(r"\{count\} points", STEPS["menu"]["description"])


async def test_pickers_of_points(hass: HomeAssistant, tecomat_entry: MockConfigEntry) -> None:
    """Removing ticks boxes (no "+ Add" button); editing picks one point from a dropdown."""
    (machine,) = tecomat_entry.subentries.values()
    result = await tecomat_entry.start_subentry_reconfigure_flow(hass, machine.subentry_id)
    remove = await step(hass, result, {"next_step_id": "remove"})
    (selector,) = remove["data_schema"].schema.values()
    assert selector.config["mode"] == SelectSelectorMode.LIST
    assert selector.config["multiple"]
    labels = [option["label"] for option in options(remove)]
    assert labels == sorted(labels, key=str.casefold)


def test_import_header_is_copyable() -> None:
    """The import form shows its header row as a code block: one line, copied as it is."""
    description = STEPS["import_points"]["description"]
    assert "```\nname,address,data_type,platform," in description


async def test_no_pick_list_once_the_plc_is_unloaded(
    hass: HomeAssistant, tecomat_entry: MockConfigEntry
) -> None:
    """The PLC was unloaded after the menu offered the pick list: the menu comes back."""
    menu = await menu_of(hass, tecomat_entry)
    assert await hass.config_entries.async_unload(tecomat_entry.entry_id)
    result = await step(hass, menu, {"next_step_id": "browse"})
    assert result["step_id"] == "menu"


async def test_a_stored_point_the_parser_refuses_still_counts_as_taken(
    hass: HomeAssistant, tecomat_entry: MockConfigEntry
) -> None:
    """A stored address the vendor's parser now refuses is compared as it was stored."""
    (machine,) = tecomat_entry.subentries.values()
    points = dict(machine.data[CONF_POINTS]) | {
        "odd": {"name": "Odd", "platform": "sensor", "address": "set time", "data_type": "INT"}
    }
    hass.config_entries.async_update_subentry(
        tecomat_entry, machine, data={**machine.data, CONF_POINTS: points}
    )
    await hass.async_block_till_done()
    menu = await menu_of(hass, tecomat_entry, "Other")
    result = await step(hass, menu, {"next_step_id": "point"})
    result = await step(
        hass, result, {"name": "x", "platform": "sensor", "address": "setTime", "data_type": "DT"}
    )
    assert result["step_id"] == "details"
