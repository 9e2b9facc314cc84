"""Reauth and reconfigure: the same checks as adding a PLC, the same PLC afterwards.

The flows alone run with the setup mocked; the reload tests set the PLC up for real.
"""

from __future__ import annotations

from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import ConfigEntryState
from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_PORT, CONF_USERNAME
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import CONF_FINGERPRINT, CONF_TLS, CONF_VENDOR, DOMAIN
from custom_components.plc_bridge.plc.http import format_fingerprint
from simulators.s7_smart import DEFAULT_PASSWORD, DEFAULT_USER, S7SmartSimulator
from tests.entries import make_entry, poll, sim_data
from tests.flows.forms import FAKE_VENDOR, FakeClient, error_message, suggested, translated

pytestmark = pytest.mark.no_pacing

CONFIG = ("config",)
flow_only = pytest.mark.usefixtures("mock_setup_entry")


async def submit(hass: HomeAssistant, result: Any, values: dict[str, Any]) -> Any:
    """Submit a form and check the answer is translated; the reload it started has run."""
    result = await hass.config_entries.flow.async_configure(result["flow_id"], values)
    await hass.async_block_till_done()
    return translated(result, *CONFIG)


@flow_only
async def test_reauth(
    hass: HomeAssistant, flow_sim: S7SmartSimulator, flow_entry: MockConfigEntry
) -> None:
    """A wrong password is refused on its field; the right one is stored and nothing else."""
    hass.config_entries.async_update_entry(
        flow_entry, data={**flow_entry.data, CONF_PASSWORD: "old"}
    )
    result = translated(await flow_entry.start_reauth_flow(hass), *CONFIG)
    assert result["step_id"] == "reauth_confirm"
    assert result["description_placeholders"] == {"name": flow_entry.title, "problem": ""}
    assert suggested(result, CONF_USERNAME) == DEFAULT_USER
    result = await submit(hass, result, {CONF_USERNAME: DEFAULT_USER, CONF_PASSWORD: "wrong"})
    assert result["errors"] == {CONF_PASSWORD: "invalid_auth"}
    assert error_message(result, CONF_PASSWORD, *CONFIG).startswith("The PLC refused the login: ")
    result = await submit(
        hass, result, {CONF_USERNAME: DEFAULT_USER, CONF_PASSWORD: DEFAULT_PASSWORD}
    )
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "reauth_successful"
    assert dict(flow_entry.data) == sim_data(flow_sim)


@flow_only
async def test_reauth_errors_without_their_field_go_to_base(
    hass: HomeAssistant, flow_sim: S7SmartSimulator, flow_entry: MockConfigEntry
) -> None:
    """The reauth form has no host or TLS field: such errors are shown on the form."""
    result = await flow_entry.start_reauth_flow(hass)
    credentials = {CONF_USERNAME: DEFAULT_USER, CONF_PASSWORD: DEFAULT_PASSWORD}
    flow_sim.new_certificate()
    await flow_sim.restart()
    result = await submit(hass, result, credentials)
    assert result["errors"] == {"base": "tls_failed"}
    await flow_sim.stop()
    result = await submit(hass, result, credentials)
    assert result["errors"] == {"base": "cannot_connect"}
    assert flow_entry.data[CONF_PASSWORD] == DEFAULT_PASSWORD


def reconfigure_input(sim: S7SmartSimulator, **changes: Any) -> dict[str, Any]:
    """Return the reconfigure form input for the simulator."""
    return {CONF_HOST: sim.host, CONF_PORT: sim.port, CONF_TLS: "pin"} | changes


@flow_only
async def test_reconfigure_same_certificate(
    hass: HomeAssistant, flow_sim: S7SmartSimulator, flow_entry: MockConfigEntry
) -> None:
    """The pinned certificate is still the PLC's: no question asked."""
    result = translated(await flow_entry.start_reconfigure_flow(hass), *CONFIG)
    assert result["step_id"] == "reconfigure_s7_smart"
    assert [str(key) for key in result["data_schema"].schema] == [CONF_HOST, CONF_PORT, CONF_TLS]
    result = await submit(hass, result, reconfigure_input(flow_sim))
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "reconfigure_successful"
    assert dict(flow_entry.data) == sim_data(flow_sim)
    assert flow_entry.title == "Boiler house PLC"  # the name the user gave stays


@flow_only
async def test_reconfigure_shows_a_changed_certificate(
    hass: HomeAssistant, flow_sim: S7SmartSimulator, flow_entry: MockConfigEntry
) -> None:
    """A PLC with a new certificate: the new fingerprint is shown, confirmed, pinned."""
    old = flow_sim.fingerprint
    flow_sim.new_certificate()
    await flow_sim.restart()
    result = await flow_entry.start_reconfigure_flow(hass)
    result = await submit(hass, result, reconfigure_input(flow_sim))
    assert result["step_id"] == "certificate"
    assert result["description_placeholders"][CONF_FINGERPRINT] == format_fingerprint(
        flow_sim.fingerprint or ""
    )
    result = await submit(hass, result, {})
    assert result["reason"] == "reconfigure_successful"
    assert flow_entry.data[CONF_FINGERPRINT] == flow_sim.fingerprint != old


@flow_only
async def test_reconfigure_errors(
    hass: HomeAssistant, flow_sim: S7SmartSimulator, flow_entry: MockConfigEntry
) -> None:
    """Errors land on the reconfigure form; a stored password gone bad shows on the form."""
    hass.config_entries.async_update_entry(
        flow_entry, data={**flow_entry.data, CONF_PASSWORD: "changed on the PLC"}
    )
    result = await flow_entry.start_reconfigure_flow(hass)
    result = await submit(hass, result, reconfigure_input(flow_sim, tls="verify"))
    assert result["step_id"] == "reconfigure_s7_smart"
    assert result["errors"] == {CONF_TLS: "tls_failed"}
    result = await submit(hass, result, reconfigure_input(flow_sim, tls="off"))
    assert result["errors"] == {"base": "invalid_auth"}
    assert flow_entry.data[CONF_TLS] == "pin"


@flow_only
@pytest.mark.parametrize(
    ("changes", "errors"),
    [
        ({CONF_HOST: "https://127.0.0.1"}, {CONF_HOST: "invalid_host"}),
        ({CONF_PORT: 0}, {CONF_PORT: "invalid_port"}),
    ],
    ids=["scheme", "port 0"],
)
async def test_reconfigure_checked_by_the_model(
    hass: HomeAssistant,
    flow_sim: S7SmartSimulator,
    flow_entry: MockConfigEntry,
    changes: dict[str, Any],
    errors: dict[str, str],
) -> None:
    """The reconfigure page is checked as the connection page: the model's error on its field,
    before anything is sent; the entry keeps its connection."""
    stored = dict(flow_entry.data)
    result = await flow_entry.start_reconfigure_flow(hass)
    result = await submit(hass, result, reconfigure_input(flow_sim, **changes))
    assert (result["step_id"], result["errors"]) == ("reconfigure_s7_smart", errors)
    assert suggested(result, next(iter(changes))) == next(iter(changes.values()))
    assert dict(flow_entry.data) == stored
    assert sum(flow_sim.calls.values()) == 0


@flow_only
async def test_reconfigure_moves_an_address_only_device(
    hass: HomeAssistant, flow_sim: S7SmartSimulator
) -> None:
    """Without a serial or MAC the PLC is its address: it may move (off mode, no pin)."""
    entry = MockConfigEntry(
        domain=DOMAIN,
        data=sim_data(flow_sim, port=1),
        unique_id="127.0.0.1:1",
    )
    entry.add_to_hass(hass)
    result = await entry.start_reconfigure_flow(hass)
    result = await submit(hass, result, reconfigure_input(flow_sim, tls="off"))
    assert result["reason"] == "reconfigure_successful"
    assert entry.unique_id == f"127.0.0.1:{flow_sim.port}"
    assert dict(entry.data) == sim_data(flow_sim, tls="off", fingerprint="")


@flow_only
async def test_reconfigure_onto_another_entry(
    hass: HomeAssistant, flow_sim: S7SmartSimulator, flow_entry: MockConfigEntry
) -> None:
    """Moving onto the address of another configured PLC aborts."""
    entry = MockConfigEntry(domain=DOMAIN, data=sim_data(flow_sim, port=1), unique_id="x:1")
    entry.add_to_hass(hass)
    result = await entry.start_reconfigure_flow(hass)
    result = await submit(hass, result, reconfigure_input(flow_sim))
    assert result["reason"] == "already_configured"
    assert entry.unique_id == "x:1"


@flow_only
@pytest.mark.parametrize(
    ("unique_id", "reason"),
    [("FAKE-1", "reconfigure_successful"), ("FAKE-2", "unique_id_mismatch")],
)
async def test_reconfigure_must_reach_the_same_plc(
    hass: HomeAssistant, fake_vendor: type[FakeClient], unique_id: str, reason: str
) -> None:
    """A device with a serial must report the serial the entry was made with."""
    data = {CONF_VENDOR: FAKE_VENDOR, CONF_HOST: "old", CONF_PORT: 8080, "vendor_options": {}}
    entry = MockConfigEntry(domain=DOMAIN, data=data, unique_id=unique_id)
    entry.add_to_hass(hass)
    result = await entry.start_reconfigure_flow(hass)
    result = await submit(hass, result, {CONF_HOST: "new", CONF_PORT: 8081})
    assert result["reason"] == reason
    assert entry.unique_id == unique_id
    assert entry.data[CONF_HOST] == ("new" if reason == "reconfigure_successful" else "old")


async def loaded_entry(hass: HomeAssistant, sim: S7SmartSimulator) -> MockConfigEntry:
    """Set up the simulator's entry with its points, known by its address."""
    entry = make_entry(hass, sim)
    hass.config_entries.async_update_entry(entry, unique_id=f"127.0.0.1:{sim.port}")
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    return entry


async def after_the_reload(
    hass: HomeAssistant, sim: S7SmartSimulator, freezer: FrozenDateTimeFactory, logins: int
) -> None:
    """Check that Home Assistant's session, made after the flow's own login, is the one kept."""
    await hass.async_block_till_done()
    assert sim.calls["login"] == logins + 2  # the flow's check, then the one setup
    await poll(hass, freezer, times=2)
    entry = hass.config_entries.async_entries(DOMAIN)[0]
    assert entry.state is ConfigEntryState.LOADED
    assert entry.runtime_data.client.metrics.session_renewals == 0
    assert sim.calls["login"] == logins + 2


@pytest.mark.parametrize("moved", [True, False])
async def test_reconfigure_sets_up_once(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    setups: list[str],
    moved: bool,
) -> None:
    """Moved or not, a reconfigure sets the PLC up once, right after the flow's login.

    The S7-200 SMART keeps one session per user: the flow's login ends Home Assistant's, so the
    entry logs in again even when nothing changed, and no poll runs on the ended session.
    """
    entry = await loaded_entry(hass, s7_smart_ha_sim)
    setups.clear()
    if moved:
        await s7_smart_ha_sim.stop()
        await s7_smart_ha_sim.start()  # on another port: the PLC moved
    logins = s7_smart_ha_sim.calls["login"]
    result = await entry.start_reconfigure_flow(hass)
    result = await submit(hass, result, reconfigure_input(s7_smart_ha_sim))
    assert result["reason"] == "reconfigure_successful"
    await after_the_reload(hass, s7_smart_ha_sim, freezer, logins)
    assert setups == [entry.entry_id]
    assert entry.title == "S7-200 SMART"


async def test_reauth_of_a_loaded_entry_sets_up_once(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    setups: list[str],
) -> None:
    """Credentials confirmed while the entry runs (data unchanged): one setup, one new login."""
    entry = await loaded_entry(hass, s7_smart_ha_sim)
    setups.clear()
    logins = s7_smart_ha_sim.calls["login"]
    result = await entry.start_reauth_flow(hass)
    result = await submit(
        hass, result, {CONF_USERNAME: DEFAULT_USER, CONF_PASSWORD: DEFAULT_PASSWORD}
    )
    assert result["reason"] == "reauth_successful"
    await after_the_reload(hass, s7_smart_ha_sim, freezer, logins)
    assert setups == [entry.entry_id]


async def test_reconfigure_of_a_failed_setup_sets_up_once(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, setups: list[str]
) -> None:
    """An entry waiting to retry (the PLC was elsewhere) is set up once with the new address."""
    entry = make_entry(hass, s7_smart_ha_sim, port=1)
    await hass.config_entries.async_setup(entry.entry_id)
    assert entry.state is ConfigEntryState.SETUP_RETRY
    setups.clear()
    result = await entry.start_reconfigure_flow(hass)
    result = await submit(hass, result, reconfigure_input(s7_smart_ha_sim))
    assert result["reason"] == "reconfigure_successful"
    await hass.async_block_till_done()
    assert setups == [entry.entry_id]
    assert entry.state is ConfigEntryState.LOADED
