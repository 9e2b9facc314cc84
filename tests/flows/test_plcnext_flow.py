"""Adding, reauthenticating and reconfiguring a PLCnext Control against its simulator."""

from __future__ import annotations

from collections.abc import AsyncGenerator
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import SOURCE_USER, ConfigEntryState
from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_PORT, CONF_USERNAME
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
import pytest
import voluptuous as vol

from custom_components.plc_bridge.const import (
    CONF_FINGERPRINT,
    CONF_OPTIONS,
    CONF_TLS,
    CONF_VENDOR,
    DOMAIN,
)
from custom_components.plc_bridge.plc.http import format_fingerprint
from simulators.plcnext import DEFAULT_PASSWORD, DEFAULT_USER, VIEWER_USER, PlcnextSimulator
from tests.entries import poll
from tests.flows.forms import error_message, suggested, translated
from tests.harness import make_plcnext_entry, plcnext_data
from tests.loopback import running

CONFIG = ("config",)
CLOCK = "Arp.Plc.Eclr/MainInstance.Clock"
flow_only = pytest.mark.usefixtures("mock_setup_entry")


@pytest.fixture
async def open_sim() -> AsyncGenerator[PlcnextSimulator]:
    """A PLCnext simulator with user authentication off in its WBM."""
    async with running(PlcnextSimulator(auth=False)) as sim:
        yield sim


async def submit(hass: HomeAssistant, result: Any, values: dict[str, Any]) -> Any:
    """Submit a config flow form; check its texts; let any reload it started run."""
    result = await hass.config_entries.flow.async_configure(result["flow_id"], values)
    await hass.async_block_till_done()
    return translated(result, *CONFIG)


async def connection_form(hass: HomeAssistant) -> dict[str, Any]:
    """Start a user flow and pick PLCnext; return its connection page."""
    result = await hass.config_entries.flow.async_init(DOMAIN, context={"source": SOURCE_USER})
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {"next_step_id": "vendor"}
    )
    result = await submit(hass, result, {CONF_VENDOR: "plcnext"})
    assert result["step_id"] == "connection_plcnext"
    return result


def connection(sim: PlcnextSimulator, **changes: Any) -> dict[str, Any]:
    """Return the connection page's input for the simulator (pinned, default user, a clock)."""
    values = {
        CONF_HOST: sim.host,
        CONF_PORT: sim.port,
        CONF_TLS: "pin",
        CONF_USERNAME: DEFAULT_USER,
        CONF_PASSWORD: DEFAULT_PASSWORD,
        "clock_variable": "MainInstance.Clock",
    }
    return {key: value for key, value in (values | changes).items() if value is not None}


async def test_connection_form_fields(hass: HomeAssistant) -> None:
    """Port 443 and a pinned certificate by default; the user may stay empty."""
    result = await connection_form(hass)
    schema = {str(marker): marker for marker in result["data_schema"].schema}
    assert list(schema) == [
        CONF_HOST,
        CONF_PORT,
        CONF_TLS,
        CONF_USERNAME,
        CONF_PASSWORD,
        "clock_variable",
    ]
    assert schema[CONF_PORT].default() == 443
    assert schema[CONF_TLS].default() == "pin"
    for field in (CONF_USERNAME, CONF_PASSWORD, "clock_variable"):
        assert not isinstance(schema[field], vol.Required), field


@flow_only
async def test_pin_name_and_entry(hass: HomeAssistant, plcnext_ha_sim: PlcnextSimulator) -> None:
    """The certificate is shown and pinned, the name suggested, the entry keyed by address."""
    result = await connection_form(hass)
    result = await submit(hass, result, connection(plcnext_ha_sim))
    assert result["step_id"] == "certificate"
    assert result["description_placeholders"][CONF_FINGERPRINT] == format_fingerprint(
        plcnext_ha_sim.fingerprint or ""
    )
    result = await submit(hass, result, {})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["title"] == "PLCnext Control 127.0.0.1"
    assert result["result"].unique_id == f"{plcnext_ha_sim.host}:{plcnext_ha_sim.port}"
    assert result["data"] == plcnext_data(plcnext_ha_sim)
    assert plcnext_ha_sim.access.logins == 1


@flow_only
async def test_without_user_authentication(hass: HomeAssistant, open_sim: PlcnextSimulator) -> None:
    """A PLC with user authentication off: empty credentials, no login, an entry."""
    result = await connection_form(hass)
    values = connection(open_sim, username=None, password=None, tls="off", clock_variable=None)
    result = await submit(hass, result, values)
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["data"] == plcnext_data(
        open_sim, username="", password="", tls="off", fingerprint="", vendor_options={}
    )
    assert open_sim.access.logins == 0
    assert open_sim.calls.get("POST auth", 0) == 0


@flow_only
@pytest.mark.parametrize(
    "changes",
    [
        {CONF_PASSWORD: "wrong"},
        {CONF_USERNAME: "nobody"},
        {CONF_USERNAME: None, CONF_PASSWORD: None},  # the PLC asks for a user
        {CONF_PASSWORD: None},  # a user without a password
    ],
    ids=["password", "user", "no user", "no password"],
)
async def test_refused_credentials(
    hass: HomeAssistant, plcnext_ha_sim: PlcnextSimulator, changes: dict[str, Any]
) -> None:
    """Credentials the PLC refuses show invalid_auth on the password; fixing them creates."""
    result = await connection_form(hass)
    result = await submit(hass, result, connection(plcnext_ha_sim, **changes))
    result = await submit(hass, result, {})  # the certificate, once
    assert result["step_id"] == "connection_plcnext"
    assert result["errors"] == {CONF_PASSWORD: "invalid_auth"}
    assert error_message(result, CONF_PASSWORD, *CONFIG).startswith("The PLC refused the login: ")
    result = await submit(hass, result, connection(plcnext_ha_sim))
    assert result["type"] is FlowResultType.CREATE_ENTRY


@flow_only
@pytest.mark.parametrize(
    ("changes", "errors"),
    [
        ({"clock_variable": "Main Clock"}, {"base": "invalid_options"}),
        ({CONF_PORT: 1}, {CONF_HOST: "cannot_connect"}),
    ],
)
async def test_connection_errors(
    hass: HomeAssistant,
    plcnext_ha_sim: PlcnextSimulator,
    changes: dict[str, Any],
    errors: dict[str, str],
) -> None:
    """A clock variable that is no path, a port nobody listens on: errors on the page."""
    result = await connection_form(hass)
    result = await submit(hass, result, connection(plcnext_ha_sim, **changes))
    assert result["errors"] == errors
    if "base" in errors:
        assert "clock variable: 'Main Clock' is not a PLCnext variable path" in error_message(
            result, "base", *CONFIG
        )
        assert plcnext_ha_sim.requests == 0


@flow_only
async def test_same_plc_aborts(hass: HomeAssistant, plcnext_ha_sim: PlcnextSimulator) -> None:
    """The same PLC address twice: already configured."""
    make_plcnext_entry(hass, plcnext_ha_sim, [])
    result = await connection_form(hass)
    result = await submit(hass, result, connection(plcnext_ha_sim))
    result = await submit(hass, result, {})
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "already_configured"


@flow_only
async def test_reauth(hass: HomeAssistant, plcnext_ha_sim: PlcnextSimulator) -> None:
    """A wrong password on its field; the right one stored with nothing else changed."""
    entry = make_plcnext_entry(hass, plcnext_ha_sim, [], password="old")
    result = translated(await entry.start_reauth_flow(hass), *CONFIG)
    assert result["step_id"] == "reauth_confirm"
    assert suggested(result, CONF_USERNAME) == DEFAULT_USER
    result = await submit(hass, result, {CONF_USERNAME: DEFAULT_USER, CONF_PASSWORD: "wrong"})
    assert result["errors"] == {CONF_PASSWORD: "invalid_auth"}
    assert "refused the user or password" in error_message(result, CONF_PASSWORD, *CONFIG)
    result = await submit(
        hass, result, {CONF_USERNAME: VIEWER_USER, CONF_PASSWORD: DEFAULT_PASSWORD}
    )
    assert result["reason"] == "reauth_successful"
    assert dict(entry.data) == plcnext_data(plcnext_ha_sim, username=VIEWER_USER)


async def test_authentication_turned_on_starts_reauth(
    hass: HomeAssistant,
    plcnext_ha_sim: PlcnextSimulator,
    freezer: FrozenDateTimeFactory,
) -> None:
    """An entry made without a user, on a PLC that now asks for one: reauth, then it runs."""
    entry = make_plcnext_entry(hass, plcnext_ha_sim, username="", password="")
    assert not await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert entry.state is ConfigEntryState.SETUP_ERROR
    (flow,) = hass.config_entries.flow.async_progress_by_handler(DOMAIN)
    assert flow["context"]["source"] == "reauth"
    result = await submit(
        hass, flow, {CONF_USERNAME: DEFAULT_USER, CONF_PASSWORD: DEFAULT_PASSWORD}
    )
    assert result["reason"] == "reauth_successful"
    await hass.async_block_till_done()
    assert entry.state is ConfigEntryState.LOADED
    await poll(hass, freezer)
    assert hass.states.get("sensor.plcnext_temperature").state == "21.5"


def reconfigure_input(sim: PlcnextSimulator, **changes: Any) -> dict[str, Any]:
    """Return the reconfigure page's input for the simulator."""
    values = {CONF_HOST: sim.host, CONF_PORT: sim.port, CONF_TLS: "pin"}
    return values | {"clock_variable": "MainInstance.Clock"} | changes


@flow_only
async def test_reconfigure(hass: HomeAssistant, plcnext_ha_sim: PlcnextSimulator) -> None:
    """No credentials on the page; a new clock variable is checked, normalized and stored."""
    entry = make_plcnext_entry(hass, plcnext_ha_sim, [])
    result = translated(await entry.start_reconfigure_flow(hass), *CONFIG)
    assert result["step_id"] == "reconfigure_plcnext"
    fields = [str(key) for key in result["data_schema"].schema]
    assert fields == [CONF_HOST, CONF_PORT, CONF_TLS, "clock_variable"]
    assert suggested(result, "clock_variable") == CLOCK
    result = await submit(hass, result, reconfigure_input(plcnext_ha_sim, clock_variable="x y"))
    assert result["errors"] == {"base": "invalid_options"}
    result = await submit(hass, result, reconfigure_input(plcnext_ha_sim, clock_variable="Main.T"))
    assert result["reason"] == "reconfigure_successful"
    assert dict(entry.data) == plcnext_data(
        plcnext_ha_sim, vendor_options={"clock_variable": "Arp.Plc.Eclr/Main.T"}
    )
    assert entry.title == "PLCnext"


@flow_only
async def test_reconfigure_moved_plc(hass: HomeAssistant, plcnext_ha_sim: PlcnextSimulator) -> None:
    """A PLC found at a new address with a new certificate: shown, pinned, the entry moves."""
    entry = make_plcnext_entry(hass, plcnext_ha_sim, [])
    old = plcnext_ha_sim.fingerprint
    await plcnext_ha_sim.stop()
    plcnext_ha_sim.new_certificate()
    await plcnext_ha_sim.start()
    result = await entry.start_reconfigure_flow(hass)
    result = await submit(hass, result, reconfigure_input(plcnext_ha_sim))
    assert result["step_id"] == "certificate"
    result = await submit(hass, result, {})
    assert result["reason"] == "reconfigure_successful"
    assert entry.data[CONF_FINGERPRINT] == plcnext_ha_sim.fingerprint != old
    assert entry.unique_id == f"{plcnext_ha_sim.host}:{plcnext_ha_sim.port}"
    assert entry.data[CONF_PASSWORD] == DEFAULT_PASSWORD
    assert entry.data[CONF_OPTIONS] == {"clock_variable": CLOCK}


@flow_only
async def test_reconfigure_without_user_authentication(
    hass: HomeAssistant, open_sim: PlcnextSimulator
) -> None:
    """An entry without a user is reconfigured without one: no login asked."""
    entry = make_plcnext_entry(
        hass, open_sim, [], username="", password="", tls="off", fingerprint=""
    )
    result = await entry.start_reconfigure_flow(hass)
    result = await submit(hass, result, reconfigure_input(open_sim, tls="off"))
    assert result["reason"] == "reconfigure_successful"
    assert open_sim.access.logins == 0
    assert entry.data[CONF_USERNAME] == ""
