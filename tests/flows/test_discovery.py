"""DHCP discovery flows: each maker's PLC probed on its simulator and added; known PLCs moved."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any
from unittest.mock import AsyncMock

from homeassistant.config_entries import SOURCE_DHCP, SOURCE_IGNORE, ConfigEntryState
from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_PORT, CONF_USERNAME
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import device_registry as dr
from homeassistant.helpers.service_info.dhcp import DhcpServiceInfo
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import CONF_MAC, CONF_TLS, CONF_VENDOR, DOMAIN
from custom_components.plc_bridge.flows import discovery
from custom_components.plc_bridge.plc.vendors import implemented
from simulators.plcnext import (
    DEFAULT_PASSWORD as PLCNEXT_PASSWORD,
    DEFAULT_USER as PLCNEXT_USER,
    PlcnextSimulator,
)
from simulators.s7 import S7Simulator
from simulators.s7_smart import DEFAULT_PASSWORD, DEFAULT_USER, S7SmartSimulator
from simulators.tecomat import (
    DEFAULT_PASSWORD as TECO_PASSWORD,
    DEFAULT_USER as TECO_USER,
    TecomatSimulator,
)
from tests.entries import add_entry
from tests.flows.forms import suggested, translated
from tests.harness import TECOMAT_SERIAL, SimFactory, s7_data

pytestmark = pytest.mark.no_pacing

CONFIG = ("config",)
SIEMENS_MAC = "28:63:36:a1:b2:c3"
TECO_MAC = "00:0a:14:12:34:56"
PHOENIX_MAC = "00:a0:45:65:43:21"

type Ports = Callable[..., None]


@pytest.fixture
def ports(monkeypatch: pytest.MonkeyPatch, unused_tcp_port_factory: Callable[[], int]) -> Ports:
    """Probe every interface on a port nothing listens on; a test moves some to its simulators."""
    probed = {vendor: unused_tcp_port_factory() for vendor in implemented()}
    monkeypatch.setattr(discovery, "PROBE_PORTS", probed)

    def move(**where: int) -> None:
        probed.update(where)

    return move


async def dhcp(hass: HomeAssistant, mac: str, host: str = "127.0.0.1") -> Any:
    """Start the flow Home Assistant starts for a DHCP sighting of the MAC at the host."""
    info = DhcpServiceInfo(ip=host, hostname="plc", macaddress=mac.replace(":", ""))
    result = await hass.config_entries.flow.async_init(
        DOMAIN, context={"source": SOURCE_DHCP}, data=info
    )
    return translated(result, *CONFIG)


async def submit(hass: HomeAssistant, result: Any, values: dict[str, Any]) -> Any:
    """Submit a form of the flow; check its texts."""
    return translated(
        await hass.config_entries.flow.async_configure(result["flow_id"], values), *CONFIG
    )


async def confirmed(hass: HomeAssistant, mac: str, family: str, vendor: str | None = None) -> Any:
    """Discover the MAC, check the confirm form names the maker; return the connection page."""
    result = await dhcp(hass, mac)
    assert result["step_id"] == "discovery_confirm"
    assert result["description_placeholders"] == {"family": family, "host": "127.0.0.1"}
    flow = hass.config_entries.flow.async_get(result["flow_id"])
    assert flow["context"]["title_placeholders"] == {"family": family, "host": "127.0.0.1"}
    return await submit(hass, result, {CONF_VENDOR: vendor} if vendor else {})


def filled_in(result: Any, port: int) -> None:
    """Check the connection page suggests the discovered host and the port that answered."""
    assert suggested(result, CONF_HOST) == "127.0.0.1"
    assert suggested(result, CONF_PORT) == port


@pytest.mark.usefixtures("mock_setup_entry")
async def test_tecomat(hass: HomeAssistant, ports: Ports, tecomat_ha_sim: TecomatSimulator) -> None:
    """A TECO MAC where TecoApi answers: offered, its page filled in, an entry with the MAC."""
    ports(tecomat=tecomat_ha_sim.port)
    result = await confirmed(hass, TECO_MAC, "Teco")
    assert result["step_id"] == "connection_tecomat"
    filled_in(result, tecomat_ha_sim.port)
    values = {CONF_HOST: "127.0.0.1", CONF_PORT: tecomat_ha_sim.port, CONF_TLS: "none"}
    values |= {CONF_USERNAME: TECO_USER, CONF_PASSWORD: TECO_PASSWORD, "auth": "digest"}
    result = await submit(hass, result, values)
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["result"].unique_id == TECOMAT_SERIAL
    assert result["data"][CONF_MAC] == TECO_MAC
    assert result["data"][CONF_HOST] == "127.0.0.1"


@pytest.mark.usefixtures("mock_setup_entry")
async def test_plcnext(hass: HomeAssistant, ports: Ports, plcnext_ha_sim: PlcnextSimulator) -> None:
    """A Phoenix Contact MAC where the REST interface answers: offered, pinned, added."""
    ports(plcnext=plcnext_ha_sim.port)
    result = await confirmed(hass, PHOENIX_MAC, "Phoenix Contact")
    assert result["step_id"] == "connection_plcnext"
    filled_in(result, plcnext_ha_sim.port)
    values = {CONF_HOST: "127.0.0.1", CONF_PORT: plcnext_ha_sim.port, CONF_TLS: "pin"}
    values |= {CONF_USERNAME: PLCNEXT_USER, CONF_PASSWORD: PLCNEXT_PASSWORD}
    result = await submit(hass, result, values)
    assert result["step_id"] == "certificate"
    result = await submit(hass, result, {})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["data"][CONF_VENDOR] == "plcnext"
    assert result["data"][CONF_MAC] == PHOENIX_MAC


@pytest.mark.usefixtures("mock_setup_entry")
async def test_s7_smart(hass: HomeAssistant, ports: Ports, flow_sim: S7SmartSimulator) -> None:
    """A Siemens MAC where only the S7-200 SMART Web API answers: no choice, its page next."""
    ports(s7_smart=flow_sim.port)
    result = await confirmed(hass, SIEMENS_MAC, "Siemens")
    assert result["step_id"] == "connection_s7_smart"
    filled_in(result, flow_sim.port)
    values = {CONF_HOST: "127.0.0.1", CONF_PORT: flow_sim.port, CONF_TLS: "pin"}
    values |= {CONF_USERNAME: DEFAULT_USER, CONF_PASSWORD: DEFAULT_PASSWORD}
    result = await submit(hass, result, values)
    result = await submit(hass, result, {})  # trust the certificate shown
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["data"][CONF_MAC] == SIEMENS_MAC
    assert flow_sim.calls["get_permission"] >= 1  # the probe's, refused without a token


@pytest.mark.usefixtures("mock_setup_entry")
async def test_s7(hass: HomeAssistant, ports: Ports, s7_ha_sims: SimFactory) -> None:
    """A Siemens MAC where only S7comm answers: S7 preselected, then rack and slot, an entry."""
    sim = await s7_ha_sims()
    ports(s7=sim.port)
    result = await confirmed(hass, SIEMENS_MAC, "Siemens")
    assert result["step_id"] == "connection_s7"
    filled_in(result, sim.port)
    result = await submit(hass, result, {CONF_HOST: "127.0.0.1", CONF_PORT: sim.port})
    result = await submit(hass, result, {"rack": 0, "slot": 1})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["result"].unique_id == S7Simulator.serial
    assert result["data"][CONF_MAC] == SIEMENS_MAC


@pytest.mark.usefixtures("mock_setup_entry")
async def test_s7_at_slot_two(hass: HomeAssistant, ports: Ports, s7_ha_sims: SimFactory) -> None:
    """An S7-300/400 CPU answers at slot 2: the rack/slot page suggests slot 2, and it connects."""
    sim = await s7_ha_sims(slot=2)
    ports(s7=sim.port)
    result = await confirmed(hass, SIEMENS_MAC, "Siemens")
    result = await submit(hass, result, {CONF_HOST: "127.0.0.1", CONF_PORT: sim.port})
    assert (suggested(result, "rack"), suggested(result, "slot")) == (0, 2)
    result = await submit(hass, result, {"rack": 0, "slot": 2})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["data"]["vendor_options"]["slot"] == 2


@pytest.mark.usefixtures("mock_setup_entry")
async def test_siemens_both_answer(
    hass: HomeAssistant, ports: Ports, s7_ha_sims: SimFactory, flow_sim: S7SmartSimulator
) -> None:
    """Both Siemens interfaces answer: the user picks one, the Web API preselected."""
    sim = await s7_ha_sims()
    ports(s7=sim.port, s7_smart=flow_sim.port)
    result = await dhcp(hass, SIEMENS_MAC)
    (field,) = result["data_schema"].schema
    assert str(field) == CONF_VENDOR
    assert field.default() == "s7_smart"
    assert result["data_schema"].schema[field].config["options"] == ["s7_smart", "s7"]
    result = await submit(hass, result, {CONF_VENDOR: "s7"})
    assert result["step_id"] == "connection_s7"
    filled_in(result, sim.port)


@pytest.mark.parametrize(
    ("mac", "slot"), [(SIEMENS_MAC, 1), (SIEMENS_MAC, 5), (TECO_MAC, 1), (PHOENIX_MAC, 1)]
)
async def test_nothing_answers(
    hass: HomeAssistant, ports: Ports, s7_ha_sims: SimFactory, mac: str, slot: int
) -> None:
    """Nothing answers, or port 102 refuses slots 1 and 2 (a drive, a panel): not offered."""
    sim = await s7_ha_sims(slot=slot)
    if slot != 1:
        ports(s7=sim.port)
    result = await dhcp(hass, mac)
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "no_interface"
    assert result["description_placeholders"]["host"] == "127.0.0.1"
    assert not hass.config_entries.flow.async_progress()


def known(hass: HomeAssistant, **data: Any) -> MockConfigEntry:
    """Add an entry of a Tecomat at 192.0.2.7, keyed by its serial, with data changes."""
    entry = MockConfigEntry(
        domain=DOMAIN,
        unique_id=TECOMAT_SERIAL,
        data={CONF_VENDOR: "tecomat", CONF_HOST: "192.0.2.7", CONF_PORT: 80} | data,
    )
    entry.add_to_hass(hass)
    return entry


@pytest.mark.parametrize("how", ["noted", "unique_id", "device", "address"])
async def test_known_plc_moves(
    hass: HomeAssistant, ports: Ports, tecomat_ha_sim: TecomatSimulator, how: str
) -> None:
    """A known PLC at a new address: its host follows, nothing is probed, no flow stays."""
    ports(tecomat=tecomat_ha_sim.port)
    entry = known(hass, **({CONF_MAC: TECO_MAC} if how in ("noted", "address") else {}))
    if how == "address":  # a PLC that reports no serial: known by host and port
        hass.config_entries.async_update_entry(entry, unique_id="192.0.2.7:80")
    if how == "unique_id":
        hass.config_entries.async_update_entry(entry, unique_id=TECO_MAC)
    if how == "device":
        dr.async_get(hass).async_get_or_create(
            config_entry_id=entry.entry_id,
            identifiers={(DOMAIN, TECOMAT_SERIAL)},
            connections={(dr.CONNECTION_NETWORK_MAC, TECO_MAC)},
        )
    result = await dhcp(hass, TECO_MAC)
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "already_configured"
    assert entry.data[CONF_HOST] == "127.0.0.1"
    if how == "address":
        assert entry.unique_id == "127.0.0.1:80"
    assert tecomat_ha_sim.calls["GetInfo"] == 0
    assert not hass.config_entries.flow.async_progress()


@pytest.mark.filterwarnings("ignore:A test tried to use socket.socket.connect")  # 127.0.0.2
@pytest.mark.parametrize("retrying", [False, True])
async def test_set_up_plc_moves(
    hass: HomeAssistant,
    ports: Ports,
    s7_ha_sims: SimFactory,
    setups: list[str],
    retrying: bool,
) -> None:
    """A PLC set up (or waiting to retry) seen at a new address is set up there, once.

    Loaded: reloaded by its update listener (the flow passes reload_on_update=False); waiting
    to retry (nothing answered at its old address): by Home Assistant, as for any discovery.
    Its device carries the MAC noted at discovery. Tests reach 127.0.0.1 only: the loaded PLC
    moves away from it, the retrying one to it.
    """
    sim = await s7_ha_sims()
    old, new = ("127.0.0.2", "127.0.0.1") if retrying else ("127.0.0.1", "127.0.0.2")
    data = s7_data(sim) | {CONF_HOST: old, CONF_MAC: SIEMENS_MAC}
    entry = add_entry(hass, title="S7", entry_id="S7MOVES", unique_id=sim.serial, data=data)
    await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert entry.state is (ConfigEntryState.SETUP_RETRY if retrying else ConfigEntryState.LOADED)
    if not retrying:
        devices = dr.async_entries_for_config_entry(dr.async_get(hass), entry.entry_id)
        connections = [list(device.connections) for device in devices]
        assert [(dr.CONNECTION_NETWORK_MAC, SIEMENS_MAC)] in connections
    before = sim.connections
    result = await dhcp(hass, SIEMENS_MAC, new)
    await hass.async_block_till_done()
    assert result["reason"] == "already_configured"
    assert entry.data[CONF_HOST] == new
    assert setups == [entry.entry_id] * 2
    if retrying:
        assert entry.state is ConfigEntryState.LOADED
        assert sim.connections == before + 1  # the setup's connection; no probe's
    else:
        assert sim.connections == before  # no probe


async def test_configured_address_not_probed(
    hass: HomeAssistant, ports: Ports, tecomat_ha_sim: TecomatSimulator
) -> None:
    """An entry already at the discovered address (without a MAC noted): no probe, no flow."""
    ports(tecomat=tecomat_ha_sim.port)
    known(hass, **{CONF_HOST: "127.0.0.1"})
    result = await dhcp(hass, TECO_MAC)
    assert result["reason"] == "already_configured"
    assert tecomat_ha_sim.calls["GetInfo"] == 0


async def test_ignored(hass: HomeAssistant, ports: Ports, tecomat_ha_sim: TecomatSimulator) -> None:
    """A discovery the user ignored stays ignored: no probe, no flow."""
    ports(tecomat=tecomat_ha_sim.port)
    MockConfigEntry(domain=DOMAIN, unique_id=TECO_MAC, source=SOURCE_IGNORE).add_to_hass(hass)
    result = await dhcp(hass, TECO_MAC)
    assert result["reason"] == "already_configured"
    assert tecomat_ha_sim.calls["GetInfo"] == 0


async def test_seen_twice(
    hass: HomeAssistant, ports: Ports, tecomat_ha_sim: TecomatSimulator, mock_setup_entry: AsyncMock
) -> None:
    """A PLC seen again while its discovery waits: one flow only."""
    ports(tecomat=tecomat_ha_sim.port)
    assert (await dhcp(hass, TECO_MAC))["step_id"] == "discovery_confirm"
    result = await dhcp(hass, TECO_MAC)
    assert result["reason"] == "already_in_progress"
    assert len(hass.config_entries.flow.async_progress()) == 1


async def test_known_plc_by_name_keeps_its_name(
    hass: HomeAssistant, ports: Ports, tecomat_ha_sim: TecomatSimulator
) -> None:
    """A PLC set up by host name is not moved to the address seen: the name follows it.

    An address in place of the name would break a certificate checked against the name.
    """
    ports(tecomat=tecomat_ha_sim.port)
    entry = known(hass, **{CONF_MAC: TECO_MAC, CONF_HOST: "plc1.factory.lan"})
    result = await dhcp(hass, TECO_MAC)
    assert result["reason"] == "already_configured"
    assert entry.data[CONF_HOST] == "plc1.factory.lan"
    assert tecomat_ha_sim.calls["GetInfo"] == 0


async def test_retrying_plc_by_name_set_up_when_seen(
    hass: HomeAssistant, ports: Ports, s7_ha_sims: SimFactory
) -> None:
    """A PLC set up by name and waiting to retry is set up again when seen; its name stays."""
    sim = await s7_ha_sims(slot=5)  # refuses the entry's slot 1 until it is "repaired"
    data = s7_data(sim) | {CONF_HOST: "localhost", CONF_MAC: SIEMENS_MAC}
    entry = add_entry(hass, title="S7", entry_id="S7NAMED", unique_id=sim.serial, data=data)
    await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert entry.state is ConfigEntryState.SETUP_RETRY
    sim.slot = 1
    result = await dhcp(hass, SIEMENS_MAC)
    await hass.async_block_till_done()
    assert result["reason"] == "already_configured"
    assert entry.state is ConfigEntryState.LOADED
    assert entry.data[CONF_HOST] == "localhost"
