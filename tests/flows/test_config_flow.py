"""Config flow: vendor, connection with certificate pinning, errors on their fields."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncGenerator
from pathlib import Path
from typing import Any
from unittest.mock import AsyncMock, patch

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import SOURCE_USER, ConfigEntryState
from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_PORT, CONF_USERNAME
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import entity_registry as er
from homeassistant.helpers.selector import NumberSelector, TextSelector
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import CONF_TLS, CONF_VENDOR, DOMAIN
from custom_components.plc_bridge.flows import base, connection_form
from custom_components.plc_bridge.flows.config_file_flow import PASTE
from custom_components.plc_bridge.model.vendor_fields import VendorField
from custom_components.plc_bridge.plc import DeviceInfo
from custom_components.plc_bridge.plc.http import format_fingerprint
from custom_components.plc_bridge.plc.vendors import VENDORS, implemented
from simulators.s7_smart import DEFAULT_PASSWORD, DEFAULT_USER, S7SmartSimulator
from tests.entries import read_edits, sim_data
from tests.flows.forms import (
    FAKE_VENDOR,
    FakeClient,
    error_message,
    strings_at,
    translated,
)

pytestmark = pytest.mark.no_pacing

CONFIG = ("config",)


async def start(hass: HomeAssistant, vendor: str = "s7_smart") -> dict[str, Any]:
    """Start a user flow and pick the vendor; return the connection form."""
    result = await hass.config_entries.flow.async_init(DOMAIN, context={"source": SOURCE_USER})
    assert result["type"] is FlowResultType.MENU
    assert result["menu_options"] == ["vendor", PASTE]
    assert set(result["menu_options"]) == set(strings_at("config", "step", "user", "menu_options"))
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {"next_step_id": "vendor"}
    )
    assert result["step_id"] == "vendor"
    translated(result, *CONFIG)
    return await hass.config_entries.flow.async_configure(result["flow_id"], {CONF_VENDOR: vendor})


def connection(sim: S7SmartSimulator, **changes: Any) -> dict[str, Any]:
    """Return the connection form input for the simulator."""
    values = {
        CONF_HOST: sim.host,
        CONF_PORT: sim.port,
        CONF_TLS: "pin",
        CONF_USERNAME: DEFAULT_USER,
        CONF_PASSWORD: DEFAULT_PASSWORD,
    }
    return values | changes


async def submit(hass: HomeAssistant, result: dict[str, Any], values: dict[str, Any]) -> Any:
    """Submit a form and check the answer is translated."""
    return translated(
        await hass.config_entries.flow.async_configure(result["flow_id"], values), *CONFIG
    )


def test_strings_copied_to_english() -> None:
    """translations/en.json is strings.json."""
    root = Path(__file__).parents[2] / "custom_components/plc_bridge"
    assert (root / "strings.json").read_text() == (root / "translations/en.json").read_text()


async def test_only_implemented_vendors_listed(hass: HomeAssistant) -> None:
    """The family list offers what PLC Bridge implements, nothing to be refused afterwards; the
    way to paste an exported configuration is the first page's other choice, not a family."""
    result = await hass.config_entries.flow.async_init(DOMAIN, context={"source": SOURCE_USER})
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {"next_step_id": "vendor"}
    )
    selector = result["data_schema"].schema[CONF_VENDOR].config
    assert selector["options"] == implemented()
    assert implemented() == list(VENDORS)
    assert selector["translation_key"] == CONF_VENDOR
    assert set(selector["options"]) <= set(strings_at("selector", CONF_VENDOR, "options"))


async def test_name_asked_once(
    hass: HomeAssistant, flow_sim: S7SmartSimulator, mock_setup_entry: AsyncMock
) -> None:
    """The entry takes the name the PLC reports (never its host): no name page of our own, as
    Home Assistant's own dialog asks the new device's name and area next."""
    result = await start(hass)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], connection(flow_sim, tls="off")
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["title"] == "S7-200 SMART 127.0.0.1"  # no name of its own: model and host
    assert "name" not in strings_at("config", "step")


async def test_pin_mode_shows_and_stores_fingerprint(
    hass: HomeAssistant, flow_sim: S7SmartSimulator, mock_setup_entry: AsyncMock
) -> None:
    """Pin mode: the fingerprint is shown for confirmation, then pinned in the entry."""
    result = translated(await start(hass), *CONFIG)
    assert result["step_id"] == "connection_s7_smart"
    schema = result["data_schema"]({CONF_HOST: "plc", CONF_USERNAME: "u", CONF_PASSWORD: "p"})
    assert schema[CONF_PORT] == 443
    assert schema[CONF_TLS] == "pin"
    result = await submit(hass, result, connection(flow_sim))
    assert result["step_id"] == "certificate"
    placeholders = result["description_placeholders"]
    assert placeholders["fingerprint"] == format_fingerprint(flow_sim.fingerprint or "")
    assert placeholders[CONF_HOST] == "127.0.0.1"
    result = await submit(hass, result, {})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["title"] == "S7-200 SMART 127.0.0.1"  # no name of its own: model and host
    assert result["data"] == sim_data(flow_sim)
    assert result["result"].unique_id == f"127.0.0.1:{flow_sim.port}"
    assert flow_sim.calls["login"] == 1
    assert mock_setup_entry.call_count == 1


async def test_verify_mode_refuses_device_ca(
    hass: HomeAssistant, flow_sim: S7SmartSimulator
) -> None:
    """Verify mode against a certificate from the CPU's own CA fails on the TLS field."""
    result = await start(hass)
    result = await submit(hass, result, connection(flow_sim, tls="verify"))
    assert result["step_id"] == "connection_s7_smart"
    assert result["errors"] == {CONF_TLS: "tls_failed"}
    assert flow_sim.calls["login"] == 0


@pytest.mark.usefixtures("mock_setup_entry")
async def test_off_mode(hass: HomeAssistant, flow_sim: S7SmartSimulator) -> None:
    """Off mode connects without a certificate check and stores no fingerprint."""
    result = await submit(hass, await start(hass), connection(flow_sim, tls="off"))
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["data"] == sim_data(flow_sim, tls="off", fingerprint="")


@pytest.mark.usefixtures("mock_setup_entry")
async def test_wrong_password_then_right(hass: HomeAssistant, flow_sim: S7SmartSimulator) -> None:
    """invalid_auth lands on the password; the confirmed certificate is not asked again."""
    result = await submit(hass, await start(hass), connection(flow_sim, password="wrong"))
    result = await submit(hass, result, {})
    assert result["step_id"] == "connection_s7_smart"
    assert result["errors"] == {CONF_PASSWORD: "invalid_auth"}
    result = await submit(hass, result, connection(flow_sim))
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["data"][CONF_PASSWORD] == DEFAULT_PASSWORD


@pytest.mark.parametrize("tls", ["pin", "off"])
async def test_host_down(hass: HomeAssistant, flow_sim: S7SmartSimulator, tls: str) -> None:
    """Nothing listening: cannot_connect on the host field, in both paths to the PLC."""
    await flow_sim.stop()
    result = await submit(hass, await start(hass), connection(flow_sim, tls=tls))
    assert result["step_id"] == "connection_s7_smart"
    assert result["errors"] == {CONF_HOST: "cannot_connect"}


@pytest.fixture
async def silent_port() -> AsyncGenerator[int]:
    """A port that accepts connections and never answers."""
    held: list[asyncio.StreamWriter] = []
    server = await asyncio.start_server(lambda _r, writer: held.append(writer), "127.0.0.1", 0)
    yield server.sockets[0].getsockname()[1]
    for writer in held:
        writer.close()
    server.close()
    await server.wait_closed()


async def test_timeout(
    hass: HomeAssistant,
    flow_sim: S7SmartSimulator,
    silent_port: int,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A PLC that never completes the handshake: timeout on the host field."""
    monkeypatch.setattr(base, "CERTIFICATE_TIMEOUT", 0.1)
    result = await submit(hass, await start(hass), connection(flow_sim, port=silent_port))
    assert result["errors"] == {CONF_HOST: "timeout"}
    assert error_message(result, CONF_HOST, *CONFIG) == (
        f"The PLC did not answer in time: no answer from 127.0.0.1:{silent_port}"
    )


async def test_not_the_protocol(hass: HomeAssistant, flow_sim: S7SmartSimulator) -> None:
    """A device that answers garbage: protocol_error on the form."""
    flow_sim.rewrite = lambda reply: {"jsonrpc": "1.0", "id": reply["id"]}
    result = await submit(hass, await start(hass), connection(flow_sim, tls="off"))
    assert result["errors"] == {"base": "protocol_error"}


async def test_unexpected_error(
    hass: HomeAssistant, flow_sim: S7SmartSimulator, caplog: pytest.LogCaptureFixture
) -> None:
    """A bug in a client shows unknown and logs the exception (never the password)."""
    with patch(
        "custom_components.plc_bridge.plc.vendors.s7_smart.S7SmartClient.connect",
        side_effect=RuntimeError("boom"),
    ):
        result = await submit(hass, await start(hass), connection(flow_sim, tls="off"))
    assert result["errors"] == {"base": "unknown"}
    assert "boom" in caplog.text
    assert DEFAULT_PASSWORD not in caplog.text


async def test_already_configured(
    hass: HomeAssistant, flow_sim: S7SmartSimulator, flow_entry: MockConfigEntry
) -> None:
    """The same PLC twice aborts."""
    result = await submit(hass, await start(hass), connection(flow_sim))
    result = await submit(hass, result, {})
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "already_configured"


@pytest.mark.usefixtures("mock_setup_entry")
async def test_vendor_without_tls_choice_or_credentials(
    hass: HomeAssistant, fake_vendor: type[FakeClient], monkeypatch: pytest.MonkeyPatch
) -> None:
    """A vendor's extra fields come from the table; its serial is the unique id."""
    monkeypatch.setitem(
        connection_form.VENDOR_FIELDS,
        FAKE_VENDOR,
        (VendorField("rack", NumberSelector(), 0), VendorField("tsap", TextSelector())),
    )
    result = await start(hass, FAKE_VENDOR)
    assert [str(key) for key in result["data_schema"].schema] == [
        CONF_HOST,
        CONF_PORT,
        "rack",
        "tsap",
    ]
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_HOST: " plc.local ", CONF_PORT: 8080.0, "rack": 2.0}
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["title"] == "Fake PLC plc.local"
    assert result["result"].unique_id == "FAKE-1"
    assert result["data"] == {
        CONF_VENDOR: FAKE_VENDOR,
        CONF_HOST: "plc.local",
        CONF_PORT: 8080,
        CONF_USERNAME: "",
        CONF_PASSWORD: "",
        CONF_TLS: "none",
        "fingerprint": "",
        "vendor_options": {"rack": 2},
    }


def test_mac_is_unique_id() -> None:
    """A device with a MAC but no serial is known by its formatted MAC."""
    info = DeviceInfo(vendor=FAKE_VENDOR, model="Fake", mac="00:0A:14:1E:28:32")
    assert base.device_unique_id(info, {}) == "00:0a:14:1e:28:32"


async def test_added_plc_and_point_come_alive(
    hass: HomeAssistant,
    flow_sim: S7SmartSimulator,
    entity_registry: er.EntityRegistry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Nothing patched: the entry the flow makes is set up, a point added later gets an entity."""
    flow_sim.set("VW10", 235)
    result = await submit(hass, await start(hass), connection(flow_sim, tls="off"))
    entry = result["result"]
    await hass.async_block_till_done()
    assert entry.state is ConfigEntryState.LOADED
    result = await hass.config_entries.subentries.async_init(
        (entry.entry_id, "device"), context={"source": SOURCE_USER}
    )
    result = await hass.config_entries.subentries.async_configure(
        result["flow_id"], {"name": "Compressor"}
    )
    result = await hass.config_entries.subentries.async_configure(
        result["flow_id"], {"next_step_id": "point"}
    )
    values = {"name": "Pressure", "platform": "sensor", "address": "VW10", "data_type": "signed"}
    result = await hass.config_entries.subentries.async_configure(result["flow_id"], values)
    result = await hass.config_entries.subentries.async_configure(
        result["flow_id"], {"scale": 0.1, "offset": 0, "read_only": True}
    )
    result = await hass.config_entries.subentries.async_configure(
        result["flow_id"], {"next_step_id": "save"}
    )
    await hass.async_block_till_done()
    await read_edits(hass, freezer)
    assert entry.state is ConfigEntryState.LOADED
    (subentry_id,) = entry.subentries
    (entity,) = [
        entity
        for entity in er.async_entries_for_config_entry(entity_registry, entry.entry_id)
        if entity.config_subentry_id == subentry_id
    ]
    assert float(hass.states.get(entity.entity_id).state) == pytest.approx(23.5)
    assert await hass.config_entries.async_unload(entry.entry_id)
