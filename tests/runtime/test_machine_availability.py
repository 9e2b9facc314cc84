"""A machine's availability address, on the S7-200 SMART simulator: read in the same poll."""

from __future__ import annotations

import logging
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import SOURCE_USER
from homeassistant.const import STATE_OFF, STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from pytest_homeassistant_custom_component.components.diagnostics import (
    get_diagnostics_for_config_entry,
)
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.plc_bridge.const import DOMAIN, SUBENTRY_DEVICE
from custom_components.plc_bridge.model.availability import (
    CONF_AVAILABILITY_ADDRESS,
    CONF_AVAILABILITY_DATA_TYPE,
    CONF_AVAILABILITY_VALUES,
    is_valid,
    parse_values,
)
from simulators.s7_smart import S7SmartSimulator
from tests.entries import add_entry, device, point, poll, sim_data
from tests.flows.forms import error_message, translated

pytestmark = pytest.mark.no_pacing

BOILER = [
    point("temperature", "Temperature", "sensor", "VW4", "signed"),
    point("p1", "Burner", "switch", "I0.3", "signed", role="state", read_only=True),
    point("p2", "Burner", "switch", "M1.0", "signed", role="command"),
]
DEVICE = ("config_subentries", SUBENTRY_DEVICE)
PUMP = [point("speed", "Speed", "sensor", "VW6", "signed")]


def plant(hass: HomeAssistant, sim: S7SmartSimulator, **availability: object) -> MockConfigEntry:
    """Add an entry with a Boiler (its availability as given) and a Pump without one."""
    boiler = device(BOILER, subentry_id="boiler", title="Boiler")
    boiler["data"] = {**boiler["data"], **availability}
    return add_entry(
        hass,
        title="S7-200 SMART",
        entry_id="01JPLCBR1DGE0000000000AVAL",
        unique_id="plc-bridge-avail",
        data=sim_data(sim),
        subentries=[boiler, device(PUMP, subentry_id="pump", title="Pump")],
    )


def changes(caplog: pytest.LogCaptureFixture) -> list[str]:
    """The log lines that say a machine's availability changed."""
    return [
        record.getMessage()
        for record in caplog.records
        if "is unavailable" in record.getMessage() or "available again" in record.getMessage()
    ]


async def test_bit_gates_the_machine(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """Bit 1: values shown; 0: the machine's entities unavailable, the others not; 1: back."""
    caplog.set_level(logging.INFO, logger="custom_components.plc_bridge")
    s7_smart_ha_sim.set("VW4", 42)
    s7_smart_ha_sim.set("VW6", 7)
    s7_smart_ha_sim.set("M0.0", 1)
    entry = plant(
        hass,
        s7_smart_ha_sim,
        **{CONF_AVAILABILITY_ADDRESS: "M0.0", CONF_AVAILABILITY_DATA_TYPE: "signed"},
    )
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert hass.states.get("sensor.boiler_temperature").state == "42"
    assert hass.states.get("sensor.pump_speed").state == "7"
    assert hass.states.get("switch.boiler_burner").state == STATE_OFF

    reads = s7_smart_ha_sim.calls["read"]
    await poll(hass, freezer)
    assert s7_smart_ha_sim.calls["read"] == reads + 1  # the availability bit costs no request

    s7_smart_ha_sim.set("M0.0", 0)
    await poll(hass, freezer, 3)
    assert hass.states.get("sensor.boiler_temperature").state == STATE_UNAVAILABLE
    assert hass.states.get("switch.boiler_burner").state == STATE_UNAVAILABLE
    assert hass.states.get("sensor.pump_speed").state == "7"
    assert changes(caplog) == [
        "S7-200 SMART: Boiler is unavailable: M0.0 says its data is not valid"
    ]

    s7_smart_ha_sim.set("M0.0", 1)
    s7_smart_ha_sim.set("VW4", 43)
    await poll(hass, freezer, 3)
    assert hass.states.get("sensor.boiler_temperature").state == "43"
    assert hass.states.get("switch.boiler_burner").state == STATE_OFF
    assert len(changes(caplog)) == 2
    assert changes(caplog)[1] == "S7-200 SMART: Boiler is available again"
    assert s7_smart_ha_sim.calls["read"] == reads + 7


async def test_value_list(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, freezer: FrozenDateTimeFactory
) -> None:
    """With a list of values, only those mean valid (a non-zero value outside it does not)."""
    s7_smart_ha_sim.set("VW4", 42)
    s7_smart_ha_sim.set("VW10", 3)
    entry = plant(
        hass,
        s7_smart_ha_sim,
        **{
            CONF_AVAILABILITY_ADDRESS: "VW10",
            CONF_AVAILABILITY_DATA_TYPE: "signed",
            CONF_AVAILABILITY_VALUES: [2.0, 3.0],
        },
    )
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert hass.states.get("sensor.boiler_temperature").state == "42"
    s7_smart_ha_sim.set("VW10", 1)
    await poll(hass, freezer)
    assert hass.states.get("sensor.boiler_temperature").state == STATE_UNAVAILABLE


def test_values() -> None:
    """The value list parses numbers; a value is valid when non-zero or listed."""
    assert parse_values(" 1; 3,5 ") == [1.0, 3.0, 5.0]
    assert is_valid(True, [])
    assert not is_valid(0, [])
    assert is_valid(3, [1.0, 3.0])
    assert not is_valid(2, [1.0, 3.0])
    assert not is_valid("on", [1.0])


async def test_flow_stores_availability(hass: HomeAssistant, flow_sim: S7SmartSimulator) -> None:
    """The machine page checks the address with the vendor's parser and stores the fields."""
    entry = MockConfigEntry(domain=DOMAIN, data=sim_data(flow_sim), version=2)
    entry.add_to_hass(hass)
    result = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_DEVICE), context={"source": SOURCE_USER}
    )
    base = {"name": "Boiler", CONF_AVAILABILITY_DATA_TYPE: "signed"}
    result = await step(hass, result, base | {CONF_AVAILABILITY_ADDRESS: "XQ9.9"})
    assert error_message(result, CONF_AVAILABILITY_ADDRESS, *DEVICE).startswith("Invalid address")
    result = await step(
        hass, result, base | {CONF_AVAILABILITY_ADDRESS: "m0.0", CONF_AVAILABILITY_VALUES: "1; x"}
    )
    assert result["errors"] == {CONF_AVAILABILITY_VALUES: "invalid_availability_values"}
    result = await step(
        hass, result, base | {CONF_AVAILABILITY_ADDRESS: "m0.0", CONF_AVAILABILITY_VALUES: "1; 3"}
    )
    assert result["type"] is FlowResultType.MENU
    result = await step(hass, result, {"next_step_id": "point"})
    tank = {"name": "Tank", "platform": "sensor", "address": "VW4", "data_type": "signed"}
    result = await step(hass, result, tank)
    result = await step(hass, result, {"read_only": True})
    result = await step(hass, result, {"next_step_id": "save"})
    (subentry,) = entry.subentries.values()
    assert subentry.data[CONF_AVAILABILITY_ADDRESS] == "M0.0"
    assert subentry.data[CONF_AVAILABILITY_DATA_TYPE] == "signed"
    assert subentry.data[CONF_AVAILABILITY_VALUES] == [1.0, 3.0]


async def step(hass: HomeAssistant, result: Any, values: dict[str, Any]) -> Any:
    """Submit a form of the machine flow; check that its texts are translated."""
    return translated(
        await hass.config_entries.subentries.async_configure(result["flow_id"], values), *DEVICE
    )


async def test_address_removed(hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator) -> None:
    """A machine whose availability address is removed shows its values at once."""
    s7_smart_ha_sim.set("VW4", 42)
    entry = plant(
        hass,
        s7_smart_ha_sim,
        **{CONF_AVAILABILITY_ADDRESS: "M0.0", CONF_AVAILABILITY_DATA_TYPE: "signed"},
    )
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert hass.states.get("sensor.boiler_temperature").state == STATE_UNAVAILABLE
    boiler = entry.subentries["boiler"]
    hass.config_entries.async_update_subentry(entry, boiler, data={"points": boiler.data["points"]})
    await hass.async_block_till_done()
    assert hass.states.get("sensor.boiler_temperature").state == "42"


async def test_diagnostics_show_each_machine_and_its_availability(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Diagnostics name every machine's availability address and whether its data is valid."""
    s7_smart_ha_sim.set("M0.0", 0)
    entry = plant(
        hass,
        s7_smart_ha_sim,
        **{CONF_AVAILABILITY_ADDRESS: "M0.0", CONF_AVAILABILITY_DATA_TYPE: "signed"},
    )
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    machines = (await get_diagnostics_for_config_entry(hass, hass_client, entry))["machines"]
    assert machines["Boiler"] == {
        "area": None,
        CONF_AVAILABILITY_ADDRESS: "M0.0",
        CONF_AVAILABILITY_DATA_TYPE: "signed",
        "data_valid": False,
    }
    assert machines["Pump"] == {"area": None, "data_valid": True}
    s7_smart_ha_sim.set("M0.0", 1)
    await poll(hass, freezer)
    machines = (await get_diagnostics_for_config_entry(hass, hass_client, entry))["machines"]
    assert machines["Boiler"]["data_valid"] is True
