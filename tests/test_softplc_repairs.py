"""Repairs a SoftPLC raises: addresses the PLC refuses, and a replaced certificate."""

from __future__ import annotations

from datetime import timedelta

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.repairs import repairs_flow_manager
from homeassistant.config_entries import ConfigEntryState
from homeassistant.const import STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import issue_registry as ir
from homeassistant.setup import async_setup_component
from pytest_homeassistant_custom_component.common import async_fire_time_changed

from custom_components.plc_bridge.const import CONF_OPTIONS, DOMAIN
from custom_components.plc_bridge.plc.vendors.softplc import SoftplcClient
from simulators.softplc import SoftplcSimulator
from simulators.softplc.datatable import File
from tests.entries import point, poll
from tests.harness import SOFTPLC_POINTS, make_softplc_entry, pem_pair

MISSING = [
    point("spare", "Spare", "sensor", "N99:0", "INT"),
    point("beyond", "Beyond", "sensor", "N7:150", "INT"),
]
"""A file the PLC does not have, and an element past the end of N7 (100 elements)."""


async def test_refused_addresses_raise_issues(
    hass: HomeAssistant,
    softplc_ha_sim: SoftplcSimulator,
    issue_registry: ir.IssueRegistry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Each refused address gets its issue while the other points read; once the PLC has the
    file, the issue goes at the next probe. Between probes a poll is still one request."""
    entry = make_softplc_entry(hass, softplc_ha_sim, [*SOFTPLC_POINTS, *MISSING])
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert entry.state is ConfigEntryState.LOADED
    assert hass.states.get("sensor.softplc_count").state == "5"  # type: ignore[union-attr]
    for point_id, address in (("spare", "N99:0"), ("beyond", "N7:150")):
        assert hass.states.get(f"sensor.softplc_{point_id}").state == STATE_UNAVAILABLE  # type: ignore[union-attr]
        issue = issue_registry.async_get_issue(
            DOMAIN, f"unknown_address_{entry.entry_id}_{point_id}"
        )
        assert issue is not None
        assert issue.translation_placeholders is not None
        assert issue.translation_placeholders["address"] == address
        assert address in issue.translation_placeholders["error"]
    requests = softplc_ha_sim.requests
    await poll(hass, freezer)
    assert softplc_ha_sim.requests - requests == 1  # the refused ones wait for the next probe

    softplc_ha_sim.files["N", 99] = File("N", 99, [42])
    freezer.tick(timedelta(seconds=SoftplcClient.probe_interval))
    async_fire_time_changed(hass)
    await hass.async_block_till_done(wait_background_tasks=True)
    assert hass.states.get("sensor.softplc_spare").state == "42"  # type: ignore[union-attr]
    assert issue_registry.async_get_issue(DOMAIN, f"unknown_address_{entry.entry_id}_spare") is None
    assert issue_registry.async_get_issue(DOMAIN, f"unknown_address_{entry.entry_id}_beyond")


async def test_replaced_certificate_repaired(
    hass: HomeAssistant,
    softplc_ha_sim: SoftplcSimulator,
    issue_registry: ir.IssueRegistry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """With a client certificate the pin is the client's own context: a PLC presenting a new
    certificate gets no request; trusting it in the repair sets the entry up again."""
    options = {key: value.strip() + "\n" for key, value in pem_pair(softplc_ha_sim).items()}
    entry = make_softplc_entry(hass, softplc_ha_sim, **{CONF_OPTIONS: options})
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    softplc_ha_sim.new_certificate()  # as after a firmware update
    await softplc_ha_sim.restart()
    requests = softplc_ha_sim.requests
    await poll(hass, freezer)
    assert softplc_ha_sim.requests == requests
    assert hass.states.get("sensor.softplc_count").state == STATE_UNAVAILABLE  # type: ignore[union-attr]
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
    assert hass.states.get("sensor.softplc_count").state == "5"  # type: ignore[union-attr]
    assert issue_registry.async_get_issue(DOMAIN, issue_id) is None
