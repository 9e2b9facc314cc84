"""A LOGO! of each generation added from the UI: generation, then its TSAPs, then a real session."""

from __future__ import annotations

from typing import Any
from unittest.mock import AsyncMock

from homeassistant.config_entries import SOURCE_USER
from homeassistant.const import CONF_HOST, CONF_PORT
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
import pytest

from custom_components.plc_bridge.const import CONF_VENDOR, DOMAIN
from simulators.logo import LogoSimulator
from tests.flows.forms import translated

CONFIG = ("config",)
DEFAULTS = {"0ba7": ("10.01", "10.00"), "0ba8": ("02.00", "20.00"), "8_x": ("02.00", "20.00")}

pytestmark = pytest.mark.usefixtures("mock_setup_entry")


async def tsap_page(hass: HomeAssistant, sim: LogoSimulator) -> Any:
    """Pick LOGO!, give host, port and generation; return the TSAP page."""
    result = await hass.config_entries.flow.async_init(DOMAIN, context={"source": SOURCE_USER})
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {"next_step_id": "vendor"}
    )
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_VENDOR: "logo"}
    )
    assert translated(result, *CONFIG)["step_id"] == "connection_logo"
    assert {str(marker) for marker in result["data_schema"].schema} == {
        "host",
        "port",
        "generation",
    }
    first = result["data_schema"](
        {CONF_HOST: sim.host, CONF_PORT: sim.port, "generation": sim.generation}
    )
    result = await hass.config_entries.flow.async_configure(result["flow_id"], first)
    assert translated(result, *CONFIG)["step_id"] == f"logo_{sim.generation}"
    return result


async def test_each_generation_added_with_its_defaults(
    hass: HomeAssistant, logo_ha_sim: LogoSimulator, mock_setup_entry: AsyncMock
) -> None:
    """The TSAP page offers the generation's pair; taken as offered, the LOGO! is added."""
    result = await tsap_page(hass, logo_ha_sim)
    offered = result["data_schema"]({})
    assert (offered["local_tsap"], offered["remote_tsap"]) == DEFAULTS[logo_ha_sim.generation]
    result = await hass.config_entries.flow.async_configure(result["flow_id"], offered)
    assert result["type"] is FlowResultType.CREATE_ENTRY
    local, remote = DEFAULTS[logo_ha_sim.generation]
    assert result["data"]["vendor_options"] == {
        "generation": logo_ha_sim.generation,
        "local_tsap": local,
        "remote_tsap": remote,
    }
    assert result["data"][CONF_VENDOR] == "logo"
    assert (
        result["result"].unique_id == f"{logo_ha_sim.host}:{logo_ha_sim.port}"
    )  # a LOGO! tells no serial
    assert logo_ha_sim.connections == 1
    assert mock_setup_entry.call_count == 1


async def test_a_tsap_the_logo_refuses_is_blamed(
    hass: HomeAssistant, logo_ha_sim: LogoSimulator
) -> None:
    """A server TSAP the LOGO! has no connection for: the error is on the remote TSAP."""
    result = await tsap_page(hass, logo_ha_sim)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {"local_tsap": "02.00", "remote_tsap": "03.01"}
    )
    assert translated(result, *CONFIG)["type"] is FlowResultType.FORM
    assert result["errors"] == {"remote_tsap": "session_refused"}
    assert logo_ha_sim.connections == 0
