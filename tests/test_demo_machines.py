"""The demo's machines on the Tecomat and PLCnext simulators, as scripts/demo_plcs.py adds them.

Each machine's table is pasted into a new device (the shutter is built on its entity's page),
each entity is driven by the action the
frontend sends and the simulator's variable must change; then the demo program runs one step
and the entities show what it did (the Overheat bit, the pump's contactor, the shutter's limit).
"""

from __future__ import annotations

from pathlib import Path
import sys
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import SOURCE_USER
from homeassistant.const import ATTR_ENTITY_ID, STATE_ON
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import entity_registry as er
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import SUBENTRY_DEVICE
from simulators.plcnext import PlcnextSimulator
from simulators.tecomat import TecomatSimulator
from tests.entries import point, poll, read_edits, set_up
from tests.flows.forms import entity_page, step
from tests.harness import make_plcnext_entry, make_tecomat_entry

sys.path.insert(0, str(Path(__file__).parents[1] / "scripts"))
from demo_plcs import JOURNEYS  # the demo check's own tables and drives

FIRST = {
    "tecomat": point("set", "Requested", "number", "Main.myObject3.value", "REAL", min=10, max=30),
    "plcnext": point("set", "Setpoint", "number", "MainInstance.Setpoint", "REAL", max=100),
}
"""The point a first user adds to each PLC before the machines (the journey's pick)."""


async def add_machine(
    hass: HomeAssistant, entry: MockConfigEntry, name: str, made: str | dict[str, Any]
) -> None:
    """Add a device through the device flow by pasting its table or filling its entity's
    page, as the demo check does."""
    result = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_DEVICE), context={"source": SOURCE_USER}
    )
    menu = await step(hass, result, {"name": name})
    if isinstance(made, dict):
        page = await entity_page(hass, menu, made["platform"])
        values = {key: value for key, value in made.items() if key != "platform"}
        menu = await step(hass, page, values)
    else:
        result = await step(hass, menu, {"next_step_id": "import_points"})
        menu = await step(hass, result, {"table": made})
    assert menu["type"] is FlowResultType.MENU, menu.get("errors")
    result = await step(hass, menu, {"next_step_id": "save"})
    assert result["type"] is FlowResultType.CREATE_ENTRY


def first_of(hass: HomeAssistant, entry: MockConfigEntry, domain: str, name: str = "") -> str:
    """Return the entity id of the entry's first entity of a domain (ending in `name`)."""
    found = [
        e.entity_id
        for e in er.async_entries_for_config_entry(er.async_get(hass), entry.entry_id)
        if e.domain == domain and e.entity_id.endswith(name)
    ]
    assert found, f"no {domain} entity {name}"
    return found[0]


async def test_tecomat_demo_machines(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, tecomat_ha_sim: TecomatSimulator
) -> None:
    """The public variables of the Tecomat's demo program hold the machines."""
    entry = await set_up(hass, make_tecomat_entry(hass, tecomat_ha_sim, [FIRST["tecomat"]]))
    await drive_machines(hass, freezer, entry, tecomat_ha_sim, "tecomat")


async def test_plcnext_demo_machines(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, plcnext_ha_sim: PlcnextSimulator
) -> None:
    """The instance variables of the PLCnext's demo project hold the machines."""
    entry = await set_up(hass, make_plcnext_entry(hass, plcnext_ha_sim, [FIRST["plcnext"]]))
    await drive_machines(hass, freezer, entry, plcnext_ha_sim, "plcnext")


async def drive_machines(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    entry: MockConfigEntry,
    sim: Any,
    vendor: str,
) -> None:
    """Every drive of the demo check changes the PLC; the program's answers show."""
    journey = JOURNEYS[vendor]
    assert [name for name, _ in journey.machines] == ["Boiler", "Shutter", "Pump"]
    for name, made in journey.machines:
        await add_machine(hass, entry, name, made)
    await read_edits(hass, freezer)
    for drive in journey.drives:
        entity_id = first_of(hass, entry, drive.domain)
        await hass.services.async_call(
            drive.domain, drive.service, {ATTR_ENTITY_ID: entity_id, **drive.data}, blocking=True
        )
        assert sim.get(drive.address) == drive.expected, (drive.domain, drive.service)
    sim.animate(450.0)  # the water at 50.0 °C, above the 22.5 °C just set
    await poll(hass, freezer)
    assert hass.states.get(first_of(hass, entry, "binary_sensor", "overheat")).state == STATE_ON
    assert hass.states.get(first_of(hass, entry, "switch")).state == STATE_ON
    assert hass.states.get(first_of(hass, entry, "cover")).state == "open"
    assert hass.states.get(first_of(hass, entry, "climate")).state == "heat"
    assert hass.states.get(first_of(hass, entry, "select")).state == "Manual"
