"""Adding a PLC from a pasted file: the same PLC twice, a moved PLC, a file of an older version."""

from __future__ import annotations

import socket

from homeassistant.config_entries import ConfigEntryState
from homeassistant.const import (
    CONF_HOST,
    CONF_NAME,
    CONF_PASSWORD,
    CONF_PORT,
    CONF_USERNAME,
)
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import area_registry as ar, device_registry as dr
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import (
    CONF_AREA,
    CONF_POINTS,
    CONF_TLS,
    DOMAIN,
    SUBENTRY_DEVICE,
)
from custom_components.plc_bridge.model.config_file import dump_config
from simulators.s7_smart import DEFAULT_PASSWORD as SMART_PASSWORD, DEFAULT_USER, S7SmartSimulator
from tests.entries import DEVICE_ID, POINTS, device, legacy_point, point, sim_data
from tests.flows.forms import suggested
from tests.test_config_file import VENDORS, confirm, export, original, paste

pytestmark = pytest.mark.no_pacing


async def test_same_plc_already_configured(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """Pasting the file of a PLC that is configured ends in already_configured; nothing added."""
    vendor = VENDORS["s7_smart"]
    entry = await original(hass, vendor, s7_smart_ha_sim, {})
    result = await paste(hass, await export(hass, entry))
    result = await confirm(hass, result, {CONF_PASSWORD: SMART_PASSWORD})
    assert (result["type"], result["reason"]) == (FlowResultType.ABORT, "already_configured")
    assert hass.config_entries.async_entries(DOMAIN) == [entry]


async def test_moved_plc_asks_its_address(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """Where nothing answers at the file's address, the connection page asks for it, filled in;
    the PLC is then added with the file's machines and options (areas where this has them)."""
    with socket.socket() as closed:
        closed.bind(("127.0.0.1", 0))
        gone = closed.getsockname()[1]
    level = point("level", "Level", "sensor", "VW10", "signed")
    boiler, annex = device(POINTS, title="Boiler"), device([level], "annex", "Annex")
    boiler["data"] = {**boiler["data"], CONF_AREA: "cellar"}
    annex["data"] = {**annex["data"], CONF_AREA: "attic"}
    entry = MockConfigEntry(
        domain=DOMAIN,
        title="Boiler house",
        data=sim_data(s7_smart_ha_sim, port=gone),
        options={"scan_interval": 30.0},
        subentries_data=[boiler, annex],
        version=2,
    )
    ar.async_get(hass).async_create("Cellar")  # and no attic
    result = await paste(hass, dump_config(entry))
    assert suggested(result, CONF_PORT) == gone  # shown before anything is sent
    result = await confirm(hass, result, {CONF_PASSWORD: SMART_PASSWORD})
    assert (result["step_id"], result["errors"]) == (
        "connection_s7_smart",
        {CONF_HOST: "cannot_connect"},
    )
    assert suggested(result, CONF_PORT) == gone
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"],
        {
            CONF_HOST: s7_smart_ha_sim.host,
            CONF_PORT: s7_smart_ha_sim.port,
            CONF_TLS: "pin",
            CONF_USERNAME: DEFAULT_USER,
            CONF_PASSWORD: SMART_PASSWORD,
        },
    )
    assert result["step_id"] == "certificate"  # the file's fingerprint is not trusted up front
    result = await confirm(hass, result, {})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    await hass.async_block_till_done()
    new = result["result"]
    assert (new.title, dict(new.options)) == ("Boiler house", {"scan_interval": 30.0})
    assert new.data[CONF_PORT] == s7_smart_ha_sim.port
    machines = {machine.title: dict(machine.data) for machine in new.subentries.values()}
    assert machines["Boiler"] == dict(entry.subentries[DEVICE_ID].data)
    assert machines["Annex"] == {CONF_POINTS: dict([level])}
    devices = dr.async_entries_for_config_entry(dr.async_get(hass), new.entry_id)
    assert {dev.name: dev.area_id for dev in devices if dev.name != "Boiler house"} == {
        "Boiler": "cellar",
        "Annex": None,
    }
    assert hass.states.get("sensor.annex_level").state == "235"


async def test_older_file_migrated(hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator) -> None:
    """A file of an older entry version is created at that version, then migrated as entries
    are: version 1's one point per subentry becomes one machine of points."""
    legacy = MockConfigEntry(
        domain=DOMAIN,
        title="Boiler house",
        data=sim_data(s7_smart_ha_sim),
        subentries_data=[legacy_point(p) for p in POINTS[:2]],
        version=1,
    )
    result = await paste(hass, dump_config(legacy))
    result = await confirm(hass, result, {CONF_PASSWORD: SMART_PASSWORD})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    await hass.async_block_till_done()
    new = result["result"]
    assert new.version == 2
    (machine,) = new.subentries.values()
    assert (machine.subentry_type, machine.title) == (SUBENTRY_DEVICE, "Boiler house points")
    names = sorted(point[CONF_NAME] for point in machine.data[CONF_POINTS].values())
    assert names == ["Pressure", "Temperature"]
    assert hass.states.get("sensor.boiler_house_points_temperature").state == "21.5"


async def test_export_while_the_plc_is_away(hass: HomeAssistant) -> None:
    """The export reads the stored configuration: it works while the PLC cannot be reached."""
    with socket.socket() as closed:
        closed.bind(("127.0.0.1", 0))
        gone = closed.getsockname()[1]
    entry = MockConfigEntry(
        domain=DOMAIN,
        title="Boiler house",
        data=sim_data(S7SmartSimulator(), port=gone) | {CONF_HOST: "127.0.0.1"},
        subentries_data=[device(POINTS, title="Boiler")],
        version=2,
    )
    entry.add_to_hass(hass)
    assert not await hass.config_entries.async_setup(entry.entry_id)
    assert entry.state is ConfigEntryState.SETUP_RETRY
    text = await export(hass, entry)
    assert f"port: {gone}\n" in text
    assert "address: VD100\n" in text
