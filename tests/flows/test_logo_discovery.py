"""DHCP discovery of a LOGO!: a Siemens MAC whose port 102 answers as a LOGO! is offered as one."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import aiohttp
from homeassistant.config_entries import SOURCE_DHCP
from homeassistant.const import CONF_HOST, CONF_PORT
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers.service_info.dhcp import DhcpServiceInfo
import pytest

from custom_components.plc_bridge.const import CONF_MAC, CONF_OPTIONS, CONF_VENDOR, DOMAIN
from custom_components.plc_bridge.plc import vendors
from custom_components.plc_bridge.plc.probe import Probe
from custom_components.plc_bridge.plc.vendors import client_class, implemented, probe_of
from custom_components.plc_bridge.plc.vendors.logo.options import DEFAULT_TSAPS
from simulators.logo import LogoSimulator
from tests.flows.forms import suggested, translated
from tests.loopback import running

pytestmark = pytest.mark.no_pacing

CONFIG = ("config",)
SIEMENS_MAC = "28:63:36:a1:b2:c3"
FOUND = {"0ba7": "0ba7", "0ba8": "0ba8", "8_x": "0ba8"}  # a LOGO! 8.x serves 0BA8's defaults

LOGO_PORT = client_class("logo").default_port  # 102: the probe's port, as the page suggests it

type Probes = Callable[..., None]


@pytest.fixture
def probes(monkeypatch: pytest.MonkeyPatch, unused_tcp_port_factory: Callable[[], int]) -> Probes:
    """Probe every interface on a port nothing listens on; a test moves some to its simulator.

    The probes themselves run unchanged; only the port each is handed is replaced.
    """
    nowhere = unused_tcp_port_factory()
    where: dict[str, int] = {}

    def redirected(vendor: str, probe: Probe) -> Probe:
        """Return the vendor's probe asking at the port the test gave it."""

        async def answers(
            host: str, port: int, session: aiohttp.ClientSession, timeout: float
        ) -> dict[str, Any] | None:
            return await probe(host, where.get(vendor, nowhere), session, timeout)

        return answers

    for vendor in implemented():
        if (probe := probe_of(vendor)) is not None:
            monkeypatch.setitem(vendors._PROBES, vendor, redirected(vendor, probe))

    def move(**to: int) -> None:
        where.update(to)

    return move


async def dhcp(hass: HomeAssistant, mac: str = SIEMENS_MAC) -> Any:
    """Start the flow Home Assistant starts for a DHCP sighting of the MAC at 127.0.0.1."""
    info = DhcpServiceInfo(ip="127.0.0.1", hostname="logo", macaddress=mac.replace(":", ""))
    result = await hass.config_entries.flow.async_init(
        DOMAIN, context={"source": SOURCE_DHCP}, data=info
    )
    return translated(result, *CONFIG)


async def submit(hass: HomeAssistant, result: Any, values: dict[str, Any]) -> Any:
    """Submit a form of the flow; check its texts."""
    return translated(
        await hass.config_entries.flow.async_configure(result["flow_id"], values), *CONFIG
    )


@pytest.mark.usefixtures("mock_setup_entry")
async def test_logo_offered_and_added(
    hass: HomeAssistant, probes: Probes, logo_ha_sim: LogoSimulator
) -> None:
    """S7 and LOGO! probed on the LOGO!'s port 102: only LOGO! answers, its pages filled in.

    The confirm page offers no other family; the connection page suggests port 102 and the
    generation whose server TSAP answered, the next page that generation's TSAPs; the entry
    notes the MAC. (The probes are handed the simulator's port in place of 102.)
    """
    probes(s7=logo_ha_sim.port, logo=logo_ha_sim.port)
    result = await dhcp(hass)
    assert result["step_id"] == "discovery_confirm"
    assert result["description_placeholders"] == {"family": "Siemens", "host": "127.0.0.1"}
    assert not result["data_schema"].schema  # one family answered: nothing to choose
    assert logo_ha_sim.calls["setup"] == 0  # the probes send no S7 job

    result = await submit(hass, result, {})
    assert result["step_id"] == "connection_logo"
    generation = FOUND[logo_ha_sim.generation]
    wanted = {CONF_HOST: "127.0.0.1", CONF_PORT: LOGO_PORT, "generation": generation}
    assert {field: suggested(result, field) for field in wanted} == wanted

    result = await submit(
        hass, result, wanted | {CONF_PORT: logo_ha_sim.port, "generation": logo_ha_sim.generation}
    )
    assert result["step_id"] == f"logo_{logo_ha_sim.generation}"
    local, remote = DEFAULT_TSAPS[logo_ha_sim.generation]
    assert (suggested(result, "local_tsap"), suggested(result, "remote_tsap")) == (local, remote)
    result = await submit(hass, result, {"local_tsap": local, "remote_tsap": remote})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["data"][CONF_VENDOR] == "logo"
    assert result["data"][CONF_MAC] == SIEMENS_MAC
    assert result["data"][CONF_OPTIONS] == {
        "generation": logo_ha_sim.generation,
        "local_tsap": local,
        "remote_tsap": remote,
    }


@pytest.mark.parametrize("where", ["nothing", "other_tsap"])
async def test_nothing_answers_as_a_logo(hass: HomeAssistant, probes: Probes, where: str) -> None:
    """Nothing on port 102, or a LOGO! serving only a TSAP of the user's own: aborted.

    A connection configured with other TSAPs cannot be found without its TSAP (READINGS row 1).
    """
    async with running(LogoSimulator("0ba8", server_tsaps={0x2100})) as sim:
        if where == "other_tsap":
            probes(s7=sim.port, logo=sim.port)
        result = await dhcp(hass)
        assert result["type"] is FlowResultType.ABORT
        assert result["reason"] == "no_interface"
        assert result["description_placeholders"]["host"] == "127.0.0.1"
        assert not hass.config_entries.flow.async_progress()
        assert sim.connections == 0
