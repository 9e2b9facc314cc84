"""A machine's save runs the one validation of the stored PLC (`PlcConfig.problems`).

A save is a menu choice, which cannot carry an error: a refusal is a form of its own that names
the problem, and submitting it leads back to the menu; nothing is stored.
"""

from __future__ import annotations

from types import MappingProxyType

from homeassistant.config_entries import ConfigSubentry
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import CONF_POINTS, DOMAIN, SUBENTRY_DEVICE
from simulators.s7_smart import S7SmartSimulator
from tests.entries import PointData, device, point, sim_data
from tests.flows.forms import error_message
from tests.flows.test_device_subentry_flow import DEVICE, add_point, new_device, step

pytestmark = pytest.mark.no_pacing

SETPOINT = {"name": "Setpoint", "platform": "number", "address": "VW20", "data_type": "signed"}
TANK = {"name": "Tank", "platform": "sensor", "address": "VD100", "data_type": "float"}


def smart_entry(hass: HomeAssistant, sim: S7SmartSimulator, *points: PointData) -> MockConfigEntry:
    """Return an S7-200 SMART entry (added, not set up) with a machine of these points, if any."""
    entry = MockConfigEntry(
        domain=DOMAIN,
        data=sim_data(sim),
        version=2,
        subentries_data=[device(points, "boiler", "Boiler")] if points else [],
    )
    entry.add_to_hass(hass)
    return entry


async def test_conflict_with_another_machine_refused_at_save(
    hass: HomeAssistant, flow_sim: S7SmartSimulator
) -> None:
    """A machine saved meanwhile made a read-only VB20, which the new machine's VW20 covers:
    the save is refused with the point form's words, and nothing is stored."""
    entry = smart_entry(hass, flow_sim)
    menu = await add_point(hass, await new_device(hass, entry, "Heating"), SETPOINT)
    assert menu["type"] is FlowResultType.MENU
    annex = point("low", "Low byte", "sensor", "VB20", "unsigned", read_only=True)[1]
    hass.config_entries.async_add_subentry(
        entry,
        ConfigSubentry(
            data=MappingProxyType({CONF_POINTS: {"low": annex}}),
            subentry_type=SUBENTRY_DEVICE,
            title="Annex",
            unique_id=None,
        ),
    )
    result = await step(hass, menu, {"next_step_id": "save"})
    assert (result["type"], result["step_id"]) == (FlowResultType.FORM, "save")
    assert result["errors"] == {"base": "save_refused"}
    assert error_message(result, "base", *DEVICE) == (
        "This machine cannot be saved as it is: Setpoint: VW20 covers data of the read-only "
        "point VB20: Home Assistant would refuse every write of it. Make VB20 writable, or "
        "choose another address."
    )
    assert [sub.title for sub in entry.subentries.values()] == ["Annex"]
    result = await step(hass, result, {})
    assert (result["type"], result["step_id"]) == (FlowResultType.MENU, "menu")


async def test_problems_stored_before_do_not_block_another_machine(
    hass: HomeAssistant, flow_sim: S7SmartSimulator
) -> None:
    """A PLC stored with a conflict (before its rule existed) still takes a machine that adds
    none; the conflict is the stored machine's to fix."""
    entry = smart_entry(
        hass,
        flow_sim,
        point("set", "Setpoint", "number", "VW20", "signed"),
        point("low", "Low byte", "sensor", "VB20", "unsigned", read_only=True),
    )
    menu = await add_point(hass, await new_device(hass, entry, "Heating"), TANK)
    result = await step(hass, menu, {"next_step_id": "save"})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert sorted(sub.title for sub in entry.subentries.values()) == ["Boiler", "Heating"]
