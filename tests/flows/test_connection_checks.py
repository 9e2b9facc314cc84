"""The connection pages and the pasted file refuse the same connection values alike.

Each bad value goes through both doors: the vendor's connection pages (the error on the field
that caused it) and a pasted file (the error on the value's line). Both words come from the one
`Problem` the model finds (`Connection.problems`, `file_problems`); nothing is stored, and the
PLC's port (a loopback listener counting connections) is never reached.
"""

from __future__ import annotations

import asyncio
from collections.abc import AsyncGenerator
from dataclasses import dataclass, field, replace
from typing import Any

from homeassistant.config_entries import SOURCE_USER
from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_PORT, CONF_USERNAME
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
import yaml

from custom_components.plc_bridge.const import CONF_OPTIONS, CONF_TLS, CONF_VENDOR, DOMAIN
from custom_components.plc_bridge.model.config_file import dump_config
from custom_components.plc_bridge.model.plc_config import Connection, Problem, file_problems
from custom_components.plc_bridge.plc.vendors import client_class
from tests.flows.forms import translated
from tests.flows.test_paste_safety import line_of, refused

pytestmark = [pytest.mark.no_pacing, pytest.mark.usefixtures("mock_setup_entry")]

CONFIG = ("config",)


@dataclass(frozen=True, slots=True)
class Listener:
    """A loopback port standing in for the PLC: it counts the connections made to it."""

    port: int
    accepted: list[int] = field(default_factory=list)


@pytest.fixture
async def listener() -> AsyncGenerator[Listener]:
    """Listen on 127.0.0.1; every connection is counted and closed at once."""
    accepted: list[int] = []

    def take(_reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        """Count the connection and close it."""
        accepted.append(1)
        writer.close()

    server = await asyncio.start_server(take, "127.0.0.1", 0)
    yield Listener(server.sockets[0].getsockname()[1], accepted)
    server.close()
    await server.wait_closed()


@dataclass(frozen=True, slots=True)
class Case:
    """A bad connection value as each door gets it, and the error both must show."""

    vendor: str
    data: dict[str, Any]  # the entry data changed: host, port
    options: dict[str, Any]  # the vendor options, as the pages take them and the file holds them
    second: tuple[str, ...]  # which of the options the second page asks
    error: tuple[str, str, str]  # the form's field and error, the file's error
    line_key: str  # the key of the file's line the error names


def case(
    vendor: str,
    error: tuple[str, str, str],
    *,
    second: tuple[str, ...] = (),
    line_key: str = "",
    options: dict[str, Any] | None = None,
    **data: Any,
) -> Case:
    """Return a case; its line is that of the first key changed unless told."""
    changed = [*data, *(options or {})]
    return Case(vendor, data, options or {}, second, error, line_key or changed[-1])


HOST = (CONF_HOST, "invalid_host", "config_bad_value")
PORT = (CONF_PORT, "invalid_port", "config_bad_value")
CASES = {
    "port 0": case("s7_smart", PORT, port=0),
    "port 70000": case("s7_smart", PORT, port=70000),
    "port not whole": case("s7_smart", PORT, port=443.5),
    "empty host": case("s7_smart", HOST, host=""),
    "host with a scheme": case("s7_smart", HOST, host="https://127.0.0.1"),
    "host with a path": case("tecomat", HOST, host="127.0.0.1/TecoApi"),
    "host with a port": case("plcnext", HOST, host="127.0.0.1:443"),
    "host with a user": case("s7", HOST, host="admin@127.0.0.1"),
    "TSAP": case(
        "s7",
        ("remote_tsap", "invalid_options", "config_connection_option"),
        options={"connection": "tsap", "remote_tsap": "zz"},
        second=("remote_tsap",),
    ),
    "LOGO! TSAP": case(
        "logo",
        ("remote_tsap", "invalid_options", "config_connection_option"),
        options={"generation": "0ba8", "remote_tsap": "zz"},
        second=("remote_tsap",),
    ),
    "clock variable": case(
        "tecomat",
        ("base", "invalid_options", "config_connection_option"),
        options={"clock_variable": "set time"},
        line_key=CONF_OPTIONS,
    ),
    "certificate outside the config folder": case(
        "softplc",
        ("client_certificate", "pem_outside_config", "config_option"),
        options={"client_certificate": "/etc/ssl/private/plc.pem"},
    ),
}


def entry_data(bad: Case, port: int) -> dict[str, Any]:
    """Return the connection the case describes, at the listener's port unless it is the fault."""
    client = client_class(bad.vendor)
    data = {
        CONF_VENDOR: bad.vendor,
        CONF_HOST: "127.0.0.1",
        CONF_PORT: port,
        CONF_TLS: client.default_tls.value,
        CONF_OPTIONS: bad.options,
    }
    return data | bad.data


def model_error(hass: HomeAssistant, data: dict[str, Any]) -> tuple[str, str, str]:
    """Return the model's first problem of a connection: form field and error, file error."""
    files = file_problems(data[CONF_VENDOR], hass.config.config_dir, data[CONF_OPTIONS], {})[1]
    problems: list[Problem] = files or list(Connection.from_data(data).problems())
    first = problems[0]
    return (first.field or "base", first.field_key, first.key)


def pasted(data: dict[str, Any]) -> str:
    """Return the file of a PLC with this connection; its vendor options written as given.

    The export leaves secrets out (a client certificate): a hand-made file may hold them.
    """
    entry = MockConfigEntry(domain=DOMAIN, title="Boiler house", data=data, version=2)
    document = yaml.safe_load(dump_config(entry))
    document["connection"][CONF_OPTIONS] = data[CONF_OPTIONS]
    document.pop("secrets", None)
    return str(yaml.safe_dump(document, sort_keys=False))


async def through_the_pages(hass: HomeAssistant, bad: Case, port: int) -> Any:
    """Pick the case's vendor and fill its connection pages with its values; return the last."""
    result = await hass.config_entries.flow.async_init(DOMAIN, context={"source": SOURCE_USER})
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {"next_step_id": "vendor"}
    )
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_VENDOR: bad.vendor}
    )
    shown = {str(marker) for marker in result["data_schema"].schema}
    values: dict[str, Any] = {CONF_HOST: "127.0.0.1", CONF_PORT: port} | bad.data
    values |= {key: "admin" for key in (CONF_USERNAME, CONF_PASSWORD) if key in shown}
    values |= {key: value for key, value in bad.options.items() if key not in bad.second}
    result = translated(
        await hass.config_entries.flow.async_configure(result["flow_id"], values), *CONFIG
    )
    if bad.second and not result["errors"]:
        second = {key: bad.options[key] for key in bad.second}
        result = translated(
            await hass.config_entries.flow.async_configure(result["flow_id"], second), *CONFIG
        )
    return result


@pytest.mark.parametrize("bad", CASES.values(), ids=CASES.keys())
async def test_pages_and_file_refuse_alike(
    hass: HomeAssistant, listener: Listener, bad: Case
) -> None:
    """The same value is refused by the connection pages on its field and by the pasted file on
    its line, each with the model's error; nothing is stored and the PLC is never reached."""
    field_name, form_error, file_error = bad.error
    data = entry_data(bad, listener.port)
    assert model_error(hass, data) == bad.error
    result = await through_the_pages(hass, bad, listener.port)
    assert result["type"] is FlowResultType.FORM
    assert result["errors"] == {field_name: form_error}
    text = pasted(data)
    key, message = await refused(hass, text)
    assert key == file_error
    assert message.startswith(f"Line {line_of(text, f'{bad.line_key}:')}:")
    assert not hass.config_entries.async_entries(DOMAIN)
    assert listener.accepted == []


async def test_reauth_refuses_as_the_model(hass: HomeAssistant, listener: Listener) -> None:
    """The reauth page of a PLC that authenticates by certificate decides by the same model:
    the same value refused on its field with the same error; nothing stored, nothing sent."""
    bad = CASES["certificate outside the config folder"]
    stored = entry_data(replace(bad, options={}), listener.port)
    entry = MockConfigEntry(domain=DOMAIN, title="Boiler house", data=stored, version=2)
    entry.add_to_hass(hass)
    result = await entry.start_reauth_flow(hass)
    assert result["step_id"] == "reauth_softplc"
    given = bad.options | {"client_key": "/etc/ssl/private/plc.key"}
    result = translated(
        await hass.config_entries.flow.async_configure(result["flow_id"], given), *CONFIG
    )
    field_name, form_error, _ = model_error(hass, stored | {CONF_OPTIONS: given})
    assert result["errors"] == {field_name: form_error} == {bad.error[0]: bad.error[1]}
    assert dict(entry.data) == stored
    assert listener.accepted == []
