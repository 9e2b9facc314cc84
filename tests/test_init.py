"""Tests of setting a PLC up and unloading it: errors, repair issues, reloads."""

from __future__ import annotations

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.repairs import repairs_flow_manager
from homeassistant.config_entries import SOURCE_REAUTH, ConfigEntryState
from homeassistant.const import CONF_SCAN_INTERVAL, STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import device_registry as dr, issue_registry as ir
from homeassistant.setup import async_setup_component
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import CONF_FINGERPRINT, CONF_TLS, DOMAIN
from custom_components.plc_bridge.plc.http import format_fingerprint
from simulators.s7_smart import S7SmartSimulator
from tests.entries import ENTRY_ID, make_entry, plc_device, poll

pytestmark = pytest.mark.no_pacing


async def test_setup_and_unload(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    setup_integration: MockConfigEntry,
    device_registry: dr.DeviceRegistry,
) -> None:
    entry = setup_integration
    assert entry.state is ConfigEntryState.LOADED
    # No serial or MAC: the device is the entry's, whatever address it moves to.
    device = plc_device(device_registry, ENTRY_ID)
    assert device is not None
    assert (device.manufacturer, device.model, device.sw_version) == (
        "Siemens",
        "S7-200 SMART",
        "Web API 1.0.0",
    )
    assert device.via_device_id is None
    assert s7_smart_ha_sim.calls["login"] == 1

    assert await hass.config_entries.async_unload(entry.entry_id)
    assert entry.state is ConfigEntryState.NOT_LOADED
    assert s7_smart_ha_sim.calls["logout"] == 1


async def test_not_ready_when_unreachable(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, s7_smart_entry: MockConfigEntry
) -> None:
    await s7_smart_ha_sim.stop()
    await hass.config_entries.async_setup(s7_smart_entry.entry_id)
    assert s7_smart_entry.state is ConfigEntryState.SETUP_RETRY
    assert s7_smart_entry.reason is not None
    assert s7_smart_entry.reason.startswith("Cannot reach the PLC: cannot reach 127.0.0.1")


async def test_auth_failed_starts_reauth(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    entry = make_entry(hass, s7_smart_ha_sim, password="wrong")
    await hass.config_entries.async_setup(entry.entry_id)
    assert entry.state is ConfigEntryState.SETUP_ERROR
    assert entry.reason == (
        "The PLC refused the login: the PLC refused the user name or password"
        " (Login failed., code 1001)"  # the PLC's own words come along
    )
    assert [
        flow["context"]["source"] for flow in entry.async_get_active_flows(hass, {SOURCE_REAUTH})
    ]


async def test_tls_off_issue_until_reconfigured(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, issue_registry: ir.IssueRegistry
) -> None:
    entry = make_entry(hass, s7_smart_ha_sim, tls="off", fingerprint="")
    assert await hass.config_entries.async_setup(entry.entry_id)
    issue = issue_registry.async_get_issue(DOMAIN, f"tls_off_{entry.entry_id}")
    assert issue is not None
    assert issue.severity is ir.IssueSeverity.WARNING
    assert issue.translation_placeholders == {"title": "S7-200 SMART", "host": "127.0.0.1"}

    hass.config_entries.async_update_entry(
        entry, data={**entry.data, CONF_TLS: "pin", CONF_FINGERPRINT: s7_smart_ha_sim.fingerprint}
    )
    await hass.async_block_till_done()
    assert entry.state is ConfigEntryState.LOADED
    assert issue_registry.async_get_issue(DOMAIN, f"tls_off_{entry.entry_id}") is None


async def test_changed_certificate_at_setup(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, issue_registry: ir.IssueRegistry
) -> None:
    """A pinned certificate that no longer matches: retry without logging in, repair by trust."""
    entry = make_entry(hass, s7_smart_ha_sim, fingerprint="00" * 32)
    await hass.config_entries.async_setup(entry.entry_id)
    assert entry.state is ConfigEntryState.SETUP_RETRY
    assert entry.reason == (
        "The secure connection to the PLC failed: "
        "the PLC presented a certificate other than the pinned one"
    )
    assert s7_smart_ha_sim.requests == 0
    issue_id = f"certificate_changed_{entry.entry_id}"
    issue = issue_registry.async_get_issue(DOMAIN, issue_id)
    assert issue is not None
    assert issue.is_fixable

    assert await async_setup_component(hass, "repairs", {})
    manager = repairs_flow_manager(hass)
    assert manager is not None
    result = await manager.async_init(DOMAIN, data={"issue_id": issue_id})
    assert result["type"] is FlowResultType.FORM
    assert result["description_placeholders"]["fingerprint"] == format_fingerprint(
        s7_smart_ha_sim.fingerprint or ""
    )
    result = await manager.async_configure(result["flow_id"], {})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    await hass.async_block_till_done()
    assert entry.data[CONF_FINGERPRINT] == s7_smart_ha_sim.fingerprint
    assert entry.state is ConfigEntryState.LOADED
    assert issue_registry.async_get_issue(DOMAIN, issue_id) is None


async def test_changed_certificate_while_loaded(  # noqa: PLR0917
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    setup_integration: MockConfigEntry,
    issue_registry: ir.IssueRegistry,
    freezer: FrozenDateTimeFactory,
    setups: list[str],
) -> None:
    """A replaced certificate stops the requests; trusting it in the repair reloads once."""
    entry = setup_integration
    setups.clear()
    s7_smart_ha_sim.new_certificate()
    await s7_smart_ha_sim.restart()
    requests = s7_smart_ha_sim.requests
    await poll(hass, freezer)
    assert s7_smart_ha_sim.requests == requests  # nothing, credentials least of all, was sent
    assert hass.states.get("sensor.s7_200_smart_temperature").state == STATE_UNAVAILABLE
    issue_id = f"certificate_changed_{entry.entry_id}"
    assert issue_registry.async_get_issue(DOMAIN, issue_id) is not None

    assert await async_setup_component(hass, "repairs", {})
    manager = repairs_flow_manager(hass)
    assert manager is not None
    result = await manager.async_init(DOMAIN, data={"issue_id": issue_id})
    result = await manager.async_configure(result["flow_id"], {})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    await hass.async_block_till_done()
    assert entry.state is ConfigEntryState.LOADED
    assert hass.states.get("sensor.s7_200_smart_temperature").state == "21.5"
    assert setups == [entry.entry_id]


async def test_certificate_fix_flow_aborts(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """The PLC cannot be reached to fetch its certificate, or the entry went away meanwhile."""
    entry = make_entry(hass, s7_smart_ha_sim, fingerprint="00" * 32)
    await hass.config_entries.async_setup(entry.entry_id)
    issue_id = f"certificate_changed_{entry.entry_id}"
    assert await async_setup_component(hass, "repairs", {})
    manager = repairs_flow_manager(hass)
    assert manager is not None
    result = await manager.async_init(DOMAIN, data={"issue_id": issue_id})
    assert result["type"] is FlowResultType.FORM
    await hass.config_entries.async_remove(entry.entry_id)
    result = await manager.async_configure(result["flow_id"], {})
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "entry_removed"

    entry = make_entry(hass, s7_smart_ha_sim, fingerprint="00" * 32)
    await hass.config_entries.async_setup(entry.entry_id)
    await s7_smart_ha_sim.stop()
    result = await manager.async_init(DOMAIN, data={"issue_id": issue_id})
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "cannot_connect"


async def test_session_issue_has_no_fix_flow(hass: HomeAssistant) -> None:
    from custom_components.plc_bridge.repairs import async_create_fix_flow

    flow = await async_create_fix_flow(hass, "session_conflict_x", {"entry_id": "x"})
    assert type(flow).__name__ == "ConfirmRepairFlow"


async def test_options_change_reloads(
    hass: HomeAssistant, setup_integration: MockConfigEntry
) -> None:
    entry = setup_integration
    hass.config_entries.async_update_entry(entry, options={CONF_SCAN_INTERVAL: 30.0})
    await hass.async_block_till_done()
    assert entry.state is ConfigEntryState.LOADED
    assert entry.runtime_data.coordinator.update_interval.total_seconds() == 30.0


async def test_removing_entry_deletes_issues(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, issue_registry: ir.IssueRegistry
) -> None:
    entry = make_entry(hass, s7_smart_ha_sim, tls="off", fingerprint="")
    assert await hass.config_entries.async_setup(entry.entry_id)
    assert issue_registry.async_get_issue(DOMAIN, f"tls_off_{entry.entry_id}")
    await hass.config_entries.async_remove(entry.entry_id)
    assert issue_registry.async_get_issue(DOMAIN, f"tls_off_{entry.entry_id}") is None
