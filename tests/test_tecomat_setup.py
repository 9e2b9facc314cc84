"""A Tecomat PLC end to end: live values, stale nonces, renamed variables, mode, diagnostics."""

from __future__ import annotations

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import ConfigEntryState
from homeassistant.const import STATE_OFF, STATE_ON, STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.helpers import entity_registry as er, issue_registry as ir
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from pytest_homeassistant_custom_component.components.diagnostics import (
    get_diagnostics_for_config_entry,
)
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.plc_bridge.const import DOMAIN
from simulators.tecomat import DEFAULT_PASSWORD, DEFAULT_USER, TecomatSimulator
from tests.entries import edit_point, point, poll, read_edits, remove_point
from tests.harness import TECOMAT_SERIAL, make_tecomat_entry

INSIDE = "sensor.fx2_cp2080_inside_temperature"
STRINGS_ISSUE = "unknown_address"


def issue_of(entry: MockConfigEntry, subentry_id: str) -> str:
    """Return the issue id of a point the PLC does not know."""
    return f"{STRINGS_ISSUE}_{entry.entry_id}_{subentry_id}"


async def test_live_values(hass: HomeAssistant, tecomat_entry: MockConfigEntry) -> None:
    """Every point of every IEC type shows the simulator's value."""
    assert tecomat_entry.state is ConfigEntryState.LOADED
    states = {
        state.entity_id: state.state
        for state in hass.states.async_all()
        if state.entity_id != "sensor.fx2_cp2080_operating_mode"
    }
    # The clock entity is off by default (its state changes at every read); its drift is on.
    assert int(states.pop("sensor.fx2_cp2080_clock_drift")) < -200_000_000  # a 2018 clock
    assert states.pop("binary_sensor.fx2_cp2080_connectivity") == STATE_ON
    assert states == {
        INSIDE: "22.1",
        "number.fx2_cp2080_requested_temperature": "23.0",
        "switch.fx2_cp2080_circulation_pump": STATE_OFF,
        "binary_sensor.fx2_cp2080_bool_1": STATE_ON,
        "sensor.fx2_cp2080_int": "-2222",
        "sensor.fx2_cp2080_salary": "70000",
        "sensor.fx2_cp2080_time": "432123.45",  # a duration in seconds
        "sensor.fx2_cp2080_element": "1.3",
        "text.fx2_cp2080_greeting": "Hello everybody",
        "datetime.fx2_cp2080_stamp": "2014-05-11T18:22:33+00:00",
        # GetInfo (3.2): the program.
        "sensor.fx2_cp2080_program": "DOC_TECOAPI v1.0",
        "sensor.fx2_cp2080_program_compiled": "2018-01-19T00:39:38+00:00",
    }


async def test_stale_nonce_keeps_entities(
    hass: HomeAssistant,
    tecomat_ha_sim: TecomatSimulator,
    tecomat_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """A renewed digest nonce mid-poll is answered again at once: nothing goes unavailable."""
    tecomat_ha_sim.set("Main.myObject2.value", 19.5)
    tecomat_ha_sim.stale_nonce()
    await poll(hass, freezer)
    assert tecomat_entry.runtime_data.coordinator.last_update_success
    assert hass.states.get(INSIDE).state == "19.5"
    assert STATE_UNAVAILABLE not in {state.state for state in hass.states.async_all()}
    assert tecomat_entry.runtime_data.client.metrics.session_renewals == 1


async def test_renamed_variable_raises_an_issue(
    hass: HomeAssistant,
    tecomat_ha_sim: TecomatSimulator,
    tecomat_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    issue_registry: ir.IssueRegistry,
) -> None:
    """Only the renamed variable's entity goes; its issue names it and leaves when it is back."""
    tecomat_ha_sim.rename("plcData.varInt", "varInteger")
    tecomat_ha_sim.set("Main.myObject2.value", 19.5)
    await poll(hass, freezer)
    unavailable = [s.entity_id for s in hass.states.async_all() if s.state == STATE_UNAVAILABLE]
    assert unavailable == ["sensor.fx2_cp2080_int"]
    assert hass.states.get(INSIDE).state == "19.5"
    issue = issue_registry.async_get_issue(DOMAIN, issue_of(tecomat_entry, "int"))
    assert issue is not None
    assert issue.translation_key == STRINGS_ISSUE
    assert issue.severity is ir.IssueSeverity.WARNING
    assert not issue.is_fixable
    placeholders = issue.translation_placeholders or {}
    assert placeholders["point"] == "Int"
    assert placeholders["address"] == "plcData.varInt"
    assert placeholders["title"] == "Fx2 CP2080"
    assert "400.005" in placeholders["error"]
    assert len(issue_registry.issues) == 1
    await poll(hass, freezer)  # still failing: still one issue
    assert len(issue_registry.issues) == 1

    tecomat_ha_sim.rename("plcData.varInteger", "varInt")
    await poll(hass, freezer, 6)  # an unknown variable is asked for again once a minute
    assert hass.states.get("sensor.fx2_cp2080_int").state == "-2222"
    assert not issue_registry.issues


async def test_removing_the_point_clears_its_issue(
    hass: HomeAssistant,
    tecomat_ha_sim: TecomatSimulator,
    tecomat_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    issue_registry: ir.IssueRegistry,
) -> None:
    """A point whose variable is gone for good: removing its subentry removes its issue."""
    tecomat_ha_sim.rename("plcData.varInt", "varInteger")
    await poll(hass, freezer)
    assert issue_registry.async_get_issue(DOMAIN, issue_of(tecomat_entry, "int")) is not None
    remove_point(hass, tecomat_entry, "int")
    await hass.async_block_till_done()
    assert tecomat_entry.state is ConfigEntryState.LOADED
    assert not issue_registry.issues
    assert hass.states.get("sensor.fx2_cp2080_int") is None


async def test_fixing_the_address_clears_the_issue(
    hass: HomeAssistant,
    tecomat_ha_sim: TecomatSimulator,
    tecomat_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    issue_registry: ir.IssueRegistry,
) -> None:
    """The repair the issue asks for: the point's subentry gets the new name, the issue goes."""
    tecomat_ha_sim.rename("plcData.varInt", "varInteger")
    await poll(hass, freezer)
    assert issue_registry.async_get_issue(DOMAIN, issue_of(tecomat_entry, "int")) is not None
    edit_point(hass, tecomat_entry, "int", address="plcData.varInteger")
    await hass.async_block_till_done()
    await read_edits(hass, freezer)
    assert hass.states.get("sensor.fx2_cp2080_int").state == "-2222"
    assert not issue_registry.issues


async def test_unknown_variable_from_the_start(
    hass: HomeAssistant, tecomat_ha_sim: TecomatSimulator, issue_registry: ir.IssueRegistry
) -> None:
    """A variable that never existed raises its issue at setup; removing the entry clears it."""
    entry = make_tecomat_entry(
        hass,
        tecomat_ha_sim,
        [
            point("typo", "Typo", "sensor", "plcData.varInz", "INT"),
            point("int", "Int", "sensor", "plcData.varInt", "INT"),
        ],
    )
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert hass.states.get("sensor.fx2_cp2080_int").state == "-2222"
    assert hass.states.get("sensor.fx2_cp2080_typo").state == STATE_UNAVAILABLE
    assert list(issue_registry.issues) == [(DOMAIN, issue_of(entry, "typo"))]
    assert await hass.config_entries.async_remove(entry.entry_id)
    assert not issue_registry.issues


@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_clock_read_only_without_clock_variable(
    hass: HomeAssistant, tecomat_ha_sim: TecomatSimulator, entity_registry: er.EntityRegistry
) -> None:
    """No clock variable: a timestamp sensor; once one is named, a datetime replaces it."""
    entry = make_tecomat_entry(hass, tecomat_ha_sim, vendor_options={"auth": "digest"})
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert hass.states.get("datetime.fx2_cp2080_plc_clock") is None
    clock = hass.states.get("sensor.fx2_cp2080_plc_clock")
    assert clock.state == "2018-02-01T00:50:39+00:00"
    assert clock.attributes["device_class"] == "timestamp"
    registered = entity_registry.async_get("sensor.fx2_cp2080_plc_clock")
    assert registered.entity_category is er.EntityCategory.DIAGNOSTIC

    options = {"auth": "digest", "clock_variable": "setTime"}
    hass.config_entries.async_update_entry(entry, data={**entry.data, "vendor_options": options})
    await hass.async_block_till_done()
    assert entity_registry.async_get("sensor.fx2_cp2080_plc_clock") is None
    assert hass.states.get("sensor.fx2_cp2080_plc_clock") is None
    assert hass.states.get("datetime.fx2_cp2080_plc_clock").state == "2018-02-01T00:50:39+00:00"


async def test_clock_entities_off_by_default(
    hass: HomeAssistant, tecomat_entry: MockConfigEntry, entity_registry: er.EntityRegistry
) -> None:
    """The clock's state changes at every read: its entity is disabled until the user wants it."""
    registered = entity_registry.async_get("datetime.fx2_cp2080_plc_clock")
    assert registered is not None
    assert registered.disabled_by is er.RegistryEntryDisabler.INTEGRATION


async def test_operating_mode(
    hass: HomeAssistant,
    tecomat_ha_sim: TecomatSimulator,
    tecomat_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    entity_registry: er.EntityRegistry,
) -> None:
    """GetInfo's RUN/HALT shows in the diagnostic mode sensor (asked once a minute)."""
    mode = "sensor.fx2_cp2080_operating_mode"
    assert hass.states.get(mode).state == "run"
    registered = entity_registry.async_get(mode)
    assert registered is not None
    assert registered.entity_category is er.EntityCategory.DIAGNOSTIC
    tecomat_ha_sim.mode = "HALT"
    await poll(hass, freezer, 6)
    assert hass.states.get(mode).state == "halt"
    assert hass.states.get(INSIDE).state == "22.1"


async def test_diagnostics(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    tecomat_ha_sim: TecomatSimulator,
    tecomat_entry: MockConfigEntry,
) -> None:
    """Diagnostics of a Tecomat PLC: settings, device, status, results; no credentials."""
    result = await get_diagnostics_for_config_entry(hass, hass_client, tecomat_entry)
    data = result["entry"]["data"]
    assert data["vendor"] == "tecomat"
    assert data["vendor_options"] == {"auth": "digest", "clock_variable": "setTime"}
    for key in ("username", "password", "host"):
        assert data[key] == "**REDACTED**"
    assert result["device"]["serial"] == "**REDACTED**"
    assert result["device"]["mac"] == "**REDACTED**"
    assert result["device"]["model"] == "Fx2 CP2080"
    assert result["status"]["mode"] == "RUN"
    assert result["status"]["extra"]["program"] == "DOC_TECOAPI v1.0"
    assert result["results"]["Main.myObject2.value|REAL"]["ok"]
    assert result["results"]["plcData.varString|STRING"]["value"] == "Hello everybody"
    assert result["poll"]["planned_requests"] == 1
    assert len(result["points"]) == 10
    text = str(result)
    for secret in (DEFAULT_PASSWORD, DEFAULT_USER, TECOMAT_SERIAL, "F8-DC-7A", "127.0.0.1"):
        assert secret not in text
