"""Config flow for S7: rack/slot or TSAPs, checked by the client, then a real connection."""

from __future__ import annotations

import asyncio
import contextlib
from typing import Any
from unittest.mock import AsyncMock

from homeassistant.config_entries import SOURCE_USER
from homeassistant.const import CONF_HOST, CONF_PORT
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import CONF_VENDOR, DOMAIN
from simulators.s7 import S7Simulator
from tests.flows.forms import error_message, suggested, translated
from tests.harness import SimFactory, s7_data

CONFIG = ("config",)
SERIAL = S7Simulator.serial
TITLE = "CPU 315-2 PN/DP 127.0.0.1"  # its station name (SZL 0x001C) is "PLC Bridge": not taken

pytestmark = pytest.mark.usefixtures("mock_setup_entry")


async def connection_form(hass: HomeAssistant) -> dict[str, Any]:
    """Start a user flow, pick S7; return the connection form."""
    result = await hass.config_entries.flow.async_init(DOMAIN, context={"source": SOURCE_USER})
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {"next_step_id": "vendor"}
    )
    result = await hass.config_entries.flow.async_configure(result["flow_id"], {CONF_VENDOR: "s7"})
    assert result["step_id"] == "connection_s7"
    return translated(result, *CONFIG)


ADDRESSING = ("rack", "slot", "local_tsap", "remote_tsap")


async def submit(hass: HomeAssistant, result: dict[str, Any], values: dict[str, Any]) -> Any:
    """Submit the connection page, then the rack/slot or TSAP page it leads to; check texts."""
    first = {key: value for key, value in values.items() if key not in ADDRESSING}
    result = translated(
        await hass.config_entries.flow.async_configure(result["flow_id"], first), *CONFIG
    )
    if result.get("step_id") in ("s7_rack_slot", "s7_tsap"):
        second = {key: value for key, value in values.items() if key in ADDRESSING}
        result = translated(
            await hass.config_entries.flow.async_configure(result["flow_id"], second), *CONFIG
        )
    return result


def where(sim: S7Simulator, **fields: Any) -> dict[str, Any]:
    """Return the connection form input for the simulator."""
    return {CONF_HOST: sim.host, CONF_PORT: sim.port} | fields


async def test_form_defaults(hass: HomeAssistant) -> None:
    """Port 102, an S7-300..1500, rack 0, slot 1 by rack/slot; no TLS choice, no credentials."""
    form = await connection_form(hass)
    fields = {str(marker) for marker in form["data_schema"].schema}
    assert fields == {"host", "port", "family", "connection"}
    values = form["data_schema"]({CONF_HOST: "plc"})
    assert values == {
        CONF_HOST: "plc",
        CONF_PORT: 102,
        "family": "s7_300_1500",
        "connection": "rack_slot",
    }
    result = await hass.config_entries.flow.async_configure(form["flow_id"], values)
    assert translated(result, *CONFIG)["step_id"] == "s7_rack_slot"
    assert {str(marker) for marker in result["data_schema"].schema} == {"rack", "slot"}
    assert result["data_schema"]({}) == {"rack": 0, "slot": 1}


async def test_tsap_fields_only_for_tsap(hass: HomeAssistant) -> None:
    """Connecting by TSAP asks the TSAPs, not rack and slot."""
    form = await connection_form(hass)
    result = await hass.config_entries.flow.async_configure(
        form["flow_id"], {CONF_HOST: "plc", CONF_PORT: 102, "connection": "tsap"}
    )
    assert translated(result, *CONFIG)["step_id"] == "s7_tsap"
    assert {str(marker) for marker in result["data_schema"].schema} == {
        "local_tsap",
        "remote_tsap",
    }


async def test_rack_slot_default(
    hass: HomeAssistant, s7_ha_sims: SimFactory, mock_setup_entry: AsyncMock
) -> None:
    """Rack 0 / slot 1: the entry is created, identified by the CPU's SZL serial."""
    sim = await s7_ha_sims()
    result = await submit(hass, await connection_form(hass), where(sim))
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["title"] == TITLE
    assert result["data"] == s7_data(sim, family="s7_300_1500")  # the client's default
    assert result["result"].unique_id == SERIAL
    assert sim.connections == 1
    assert sim.calls["szl"] >= 2  # order code (0x0011) and identity (0x001C)
    assert mock_setup_entry.call_count == 1


async def test_slot_two(hass: HomeAssistant, s7_ha_sims: SimFactory) -> None:
    """A CPU in slot 2 (S7-400) refuses slot 1 on the slot field of its page, then takes slot 2."""
    sim = await s7_ha_sims(slot=2)
    form = await connection_form(hass)
    result = await submit(hass, form, where(sim, rack=0, slot=1))
    assert result["type"] is FlowResultType.FORM
    assert result["step_id"] == "s7_rack_slot"
    assert result["errors"] == {"slot": "session_refused"}
    assert sim.connections == 0
    result = await submit(hass, result, {"rack": 0.0, "slot": 2.0})  # as the UI sends
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["data"] == s7_data(sim, slot=2, family="s7_300_1500")
    assert result["result"].unique_id == SERIAL


async def test_tsap(hass: HomeAssistant, s7_ha_sims: SimFactory) -> None:
    """Connection by TSAP (S7-200 CP 243-1 style): "10.01" reaches a CPU called 0x1001."""
    sim = await s7_ha_sims(remote_tsap=0x1001)
    result = await submit(
        hass, await connection_form(hass), where(sim, connection="tsap", remote_tsap=" 10.01 ")
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["data"]["vendor_options"] == {
        "connection": "tsap",
        "local_tsap": "01.00",
        "remote_tsap": "10.01",
        "family": "s7_300_1500",
    }
    assert result["result"].unique_id == SERIAL
    assert sim.connections == 1


async def test_s7_200_by_tsap(hass: HomeAssistant, s7_ha_sims: SimFactory) -> None:
    """An S7-200 with a CP 243-1: its family is stored for its timer and counter areas."""
    sim = await s7_ha_sims(remote_tsap=0x1000, family="s7_200")
    result = await submit(
        hass,
        await connection_form(hass),
        where(sim, family="s7_200", connection="tsap", remote_tsap="10.00"),
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["data"]["vendor_options"]["family"] == "s7_200"


async def test_tsap_wrong_remote(hass: HomeAssistant, s7_ha_sims: SimFactory) -> None:
    """A TSAP the CPU does not serve is refused on the remote TSAP field of the TSAP page."""
    sim = await s7_ha_sims(remote_tsap=0x1001)
    result = await submit(
        hass, await connection_form(hass), where(sim, connection="tsap", remote_tsap="10.02")
    )
    assert result["step_id"] == "s7_tsap"
    assert result["errors"] == {"remote_tsap": "session_refused"}
    assert error_message(result, "remote_tsap", *CONFIG).startswith(
        f"The PLC answers at this host and port but refused the connection with this setting: "
        f"cannot connect to {sim.host}:{sim.port} (TSAP 10.02)"
    )
    result = await submit(hass, result, {"remote_tsap": "10.01"})
    assert result["type"] is FlowResultType.CREATE_ENTRY


async def refuse_by_disconnect(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
    """Answer a COTP connection request with a disconnect request, as a CPU may for a bad TSAP."""
    with contextlib.suppress(OSError, asyncio.IncompleteReadError):
        await reader.readexactly(4)
        writer.write(bytes([3, 0, 0, 11, 6, 0x80, 0, 0, 0, 1, 0]))  # TPKT, COTP DR
        await writer.drain()
    writer.close()


async def test_slot_refused_with_a_disconnect_request(hass: HomeAssistant) -> None:
    """A CPU that refuses a slot with a COTP disconnect request: the slot is blamed too."""
    server = await asyncio.start_server(refuse_by_disconnect, "127.0.0.1", 0)
    port = server.sockets[0].getsockname()[1]
    async with server:
        result = await submit(
            hass, await connection_form(hass), {CONF_HOST: "127.0.0.1", CONF_PORT: port, "slot": 3}
        )
    assert result["step_id"] == "s7_rack_slot"
    assert result["errors"] == {"slot": "session_refused"}


async def test_nothing_at_the_port(hass: HomeAssistant, unused_tcp_port: int) -> None:
    """Where nothing answers at the host and port, page 1 says so on the host field."""
    form = await connection_form(hass)
    result = await submit(hass, form, {CONF_HOST: "127.0.0.1", CONF_PORT: unused_tcp_port})
    assert result["step_id"] == "connection_s7"
    assert result["errors"] == {CONF_HOST: "cannot_connect"}


@pytest.mark.parametrize(
    ("fields", "problem"),
    [
        ({"connection": "tsap"}, "remote_tsap is needed to connect by TSAP, e.g. 10.01"),
        (
            {"connection": "tsap", "remote_tsap": "10:01"},
            "remote_tsap '10:01' is not a TSAP; write it as STEP 7 does, e.g. 10.01",
        ),
    ],
)
async def test_invalid_options(
    hass: HomeAssistant, s7_ha_sims: SimFactory, fields: dict[str, Any], problem: str
) -> None:
    """Options the client refuses are shown with its words on their field; nothing connects."""
    sim = await s7_ha_sims(remote_tsap=0x1001)
    result = await submit(hass, await connection_form(hass), where(sim, **fields))
    assert result["type"] is FlowResultType.FORM
    assert result["errors"] == {"remote_tsap": "invalid_options"}
    assert result["description_placeholders"] == {"problem": problem}
    assert error_message(result, "remote_tsap", *CONFIG) == (
        f"The connection settings are not valid: {problem}"
    )
    assert sim.requests == 0
    assert sim.connections == 0


async def test_already_configured(hass: HomeAssistant, s7_ha_sims: SimFactory) -> None:
    """The same CPU (same serial) under another address is refused."""
    sim = await s7_ha_sims()
    MockConfigEntry(domain=DOMAIN, unique_id=SERIAL, data=s7_data(sim, slot=3)).add_to_hass(hass)
    result = await submit(hass, await connection_form(hass), where(sim))
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "already_configured"
    assert len(hass.config_entries.async_entries(DOMAIN)) == 1


async def test_reconfigure_to_tsap(hass: HomeAssistant, s7_ha_sims: SimFactory) -> None:
    """A configured CPU moves to connection by TSAP; the same serial keeps the entry."""
    sim = await s7_ha_sims(remote_tsap=0x0302)
    entry = MockConfigEntry(domain=DOMAIN, unique_id=SERIAL, data=s7_data(sim))
    entry.add_to_hass(hass)
    result = translated(await entry.start_reconfigure_flow(hass), *CONFIG)
    assert result["step_id"] == "reconfigure_s7"
    result = await submit(hass, result, where(sim))
    assert result["errors"] == {"slot": "session_refused"}
    result = await submit(
        hass,
        await entry.start_reconfigure_flow(hass),
        where(sim, connection="tsap", local_tsap="10.00", remote_tsap="0x0302"),
    )
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "reconfigure_successful"
    assert entry.data["vendor_options"] == {
        "connection": "tsap",
        "local_tsap": "10.00",
        "remote_tsap": "03.02",
        "family": "s7_300_1500",
    }


async def test_reconfigure_suggests_the_stored_way(
    hass: HomeAssistant, s7_ha_sims: SimFactory
) -> None:
    """Reconfiguring shows the stored rack and slot on the second page, and no login fields."""
    sim = await s7_ha_sims(slot=2)
    entry = MockConfigEntry(
        domain=DOMAIN, unique_id=SERIAL, title="Press", data=s7_data(sim, slot=2)
    )
    entry.add_to_hass(hass)
    result = translated(await entry.start_reconfigure_flow(hass), *CONFIG)
    assert [str(marker) for marker in result["data_schema"].schema] == [
        CONF_HOST,
        CONF_PORT,
        "family",
        "connection",
    ]
    assert suggested(result, CONF_HOST) == sim.host
    result = await hass.config_entries.flow.async_configure(result["flow_id"], where(sim))
    assert translated(result, *CONFIG)["step_id"] == "s7_rack_slot"
    assert (suggested(result, "rack"), suggested(result, "slot")) == (0, 2)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {"rack": 0, "slot": 2}
    )
    assert result["reason"] == "reconfigure_successful"
    assert entry.title == "Press"
