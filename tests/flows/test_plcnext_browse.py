"""Picking points from a PLCnext Control's variable dictionary, on its simulator."""

from __future__ import annotations

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import ConfigEntryState
from homeassistant.const import STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import entity_registry as er
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import CONF_POINTS
from simulators.plcnext import PlcnextSimulator
from tests.entries import point, poll, read_edits
from tests.flows.forms import MACHINE, browse, error_message, listed, step
from tests.harness import PLCNEXT_POINTS, make_plcnext_entry

MAIN = "Arp.Plc.Eclr/MainInstance."


def label(path: str, kind: str) -> str:
    """Return the pick list's label of a variable: its path and type (the path said once)."""
    return f"{path} ({kind})"


async def test_pick_list_from_the_dictionary(
    hass: HomeAssistant, plcnext_entry: MockConfigEntry
) -> None:
    """Every HMI variable with its declared type; structures and arrays as leaves."""
    labels = listed(await browse(hass, plcnext_entry, "", name="Oven"))
    for shown in (
        label(MAIN + "Precise", "LREAL"),
        label(MAIN + "Counter", "DINT"),
        label(MAIN + "Big", "ULINT"),
        label(MAIN + "Label", "WSTRING"),
        label(MAIN + "Runtime", "TIME"),
        label(MAIN + "Uptime", "LTIME"),
        label(MAIN + "Clock", "DT"),
        label(MAIN + "Today", "DATE"),
        # A structure's members: typed by a register answer, not guessed from JSON
        label(MAIN + "Recipe.Name", "STRING"),
        label(MAIN + "Recipe.Weight", "REAL"),
        label(MAIN + "Recipe.Steps[1]", "DINT"),  # an array in a structure: bounds of its type
        label(MAIN + "Levels[1]", "INT"),  # the type dictionary's element type and first index
        label(MAIN + "Levels[4]", "INT"),
        label("Arp.Plc.Eclr/GlobalFlag", "BOOL"),
    ):
        assert shown in labels, shown
    assert label(MAIN + "Levels[0]", "INT") not in labels
    assert label(MAIN + "Recipe.Steps[0]", "DINT") not in labels
    assert not any(f"{MAIN}Recipe (" in shown for shown in labels)


async def test_picks_keep_types_and_read_only_flags(
    hass: HomeAssistant, plcnext_ha_sim: PlcnextSimulator, freezer: FrozenDateTimeFactory
) -> None:
    """Read-only variables become sensors; writable ones switches, numbers, texts; all read."""
    plcnext_entry = make_plcnext_entry(hass, plcnext_ha_sim, PLCNEXT_POINTS[:1])
    assert await hass.config_entries.async_setup(plcnext_entry.entry_id)
    await hass.async_block_till_done()
    result = await browse(hass, plcnext_entry, "MainInstance", name="Oven")
    labels = listed(result)
    names = (("Alarm", "BOOL"), ("Counter", "DINT"), ("Speed", "INT"), ("Label", "WSTRING"))
    ticked = [labels[label(MAIN + name, kind)] for name, kind in (*names, ("Today", "DATE"))]
    result = await step(hass, result, {"variables": ticked})
    assert result["type"] is FlowResultType.MENU
    result = await step(hass, result, {"next_step_id": "save"})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    await hass.async_block_till_done()
    (oven,) = [s for s in plcnext_entry.subentries.values() if s.title == "Oven"]
    points = {data["address"]: data for data in oven.data[CONF_POINTS].values()}
    shown = {
        address.removeprefix(MAIN): (data["platform"], data["data_type"], data["read_only"])
        for address, data in points.items()
    }
    assert shown == {
        "Alarm": ("binary_sensor", "BOOL", True),
        "Counter": ("sensor", "DINT", True),
        "Speed": ("number", "INT", False),
        "Label": ("text", "WSTRING", False),
        "Today": ("datetime", "DATE", False),
    }
    assert plcnext_entry.state is ConfigEntryState.LOADED
    entities = er.async_entries_for_config_entry(er.async_get(hass), plcnext_entry.entry_id)
    added = {e.entity_id for e in entities if e.config_subentry_id == oven.subentry_id}
    assert len(added) == 5
    await read_edits(hass, freezer)
    states = {entity_id: hass.states.get(entity_id).state for entity_id in added}
    assert STATE_UNAVAILABLE not in states.values(), states
    assert states["binary_sensor.oven_alarm"] == "on"  # named "Alarm", not by its path
    assert states["sensor.oven_counter"] == "799244562"
    assert states["number.oven_speed"] == "-1200"
    assert states["text.oven_label"] == "Grüße ✓"
    assert states["datetime.oven_today"].startswith("2026-11-2")
    await poll(hass, freezer)  # the first poll after the edit registers the new group
    await poll(hass, freezer)  # then a poll is one read
    assert plcnext_entry.runtime_data.client.metrics.last_poll_requests == 1


async def test_configured_variables_are_not_listed(
    hass: HomeAssistant, plcnext_entry: MockConfigEntry
) -> None:
    """A variable that is a point already is not offered again."""
    labels = listed(await browse(hass, plcnext_entry, "temperature", name="Oven"))
    assert labels == {}
    labels = listed(await browse(hass, plcnext_entry, "levels", name="Oven"))
    assert label(MAIN + "Levels[2]", "INT") not in labels
    assert label(MAIN + "Levels[3]", "INT") in labels


async def test_dictionary_refused(
    hass: HomeAssistant, plcnext_ha_sim: PlcnextSimulator, plcnext_entry: MockConfigEntry
) -> None:
    """A dictionary the PLC refuses: its words on the form, and back to the menu."""
    plcnext_ha_sim.access.users.clear()  # the token is refused and no login works any more
    plcnext_ha_sim.access.expire_tokens()
    result = await browse(hass, plcnext_entry, "x", name="Oven")
    assert result["errors"] == {"base": "browse_failed"}
    assert "refused the user or password" in error_message(result, "base", *MACHINE)
    menu = await step(hass, result, {})
    assert menu["type"] is FlowResultType.MENU


async def test_points_stored_with_a_short_path_are_not_offered_again(
    hass: HomeAssistant, plcnext_ha_sim: PlcnextSimulator
) -> None:
    """A point kept as `MainInstance.Counter` is the dictionary's full path: not listed twice."""
    entry = make_plcnext_entry(
        hass,
        plcnext_ha_sim,
        [point("counter", "Counter", "sensor", "MainInstance.Counter", "DINT")],
    )
    assert await hass.config_entries.async_setup(entry.entry_id)
    labels = listed(await browse(hass, entry, "Counter", name="Oven"))
    assert label(MAIN + "Counter", "DINT") not in labels
