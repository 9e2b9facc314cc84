"""Config flow, reconfigure and reauth of a SoftPLC against its simulator: client certificates."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from homeassistant.config_entries import SOURCE_USER
from homeassistant.const import CONF_HOST, CONF_PORT
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import (
    CONF_FINGERPRINT,
    CONF_OPTIONS,
    CONF_TLS,
    CONF_VENDOR,
    DOMAIN,
)
from custom_components.plc_bridge.plc.http import format_fingerprint
from simulators.softplc import SoftplcSimulator
from tests.flows.forms import error_message, suggested, translated
from tests.harness import make_softplc_entry, pem_pair

CONFIG = ("config",)
CERTIFICATE, KEY = "client_certificate", "client_key"
flow_only = pytest.mark.usefixtures("mock_setup_entry")


async def connection_form(hass: HomeAssistant) -> dict[str, Any]:
    """Start a user flow and pick SoftPLC; return its connection form."""
    result = await hass.config_entries.flow.async_init(DOMAIN, context={"source": SOURCE_USER})
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {"next_step_id": "vendor"}
    )
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_VENDOR: "softplc"}
    )
    assert result["step_id"] == "connection_softplc"
    return translated(result, *CONFIG)


def connection(sim: SoftplcSimulator, **changes: Any) -> dict[str, Any]:
    """Return the connection form input for the simulator (pinned when it speaks TLS)."""
    values = {CONF_HOST: sim.host, CONF_PORT: sim.port, CONF_TLS: "pin" if sim.tls else "none"}
    return values | changes


async def submit(hass: HomeAssistant, result: Any, values: dict[str, Any]) -> Any:
    """Submit a form; check the answer is translated and whatever it started has run."""
    result = await hass.config_entries.flow.async_configure(result["flow_id"], values)
    await hass.async_block_till_done()
    return translated(result, *CONFIG)


async def test_connection_form_fields(hass: HomeAssistant) -> None:
    """Host, port 80, no TLS by default, then the optional client certificate and key."""
    result = await connection_form(hass)
    schema = {str(marker): marker for marker in result["data_schema"].schema}
    assert list(schema) == [CONF_HOST, CONF_PORT, CONF_TLS, CERTIFICATE, KEY]
    assert schema[CONF_PORT].default() == 80
    assert schema[CONF_TLS].default() == "none"
    tls = result["data_schema"].schema[schema[CONF_TLS]].config["options"]
    assert tls == ["none", "pin", "verify", "off"]


@flow_only
async def test_plain_http(hass: HomeAssistant, softplc_http_ha_sim: SoftplcSimulator) -> None:
    """Over plain HTTP with no certificate: one GET /dt, then the entry, named "SoftPLC"."""
    result = await connection_form(hass)
    result = await submit(hass, result, connection(softplc_http_ha_sim))
    assert softplc_http_ha_sim.requests == 1  # GET /dt; no certificate, so no PUT
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["title"] == "SoftPLC"
    assert result["result"].unique_id == f"{softplc_http_ha_sim.host}:{softplc_http_ha_sim.port}"
    assert result["data"] == {
        CONF_VENDOR: "softplc",
        CONF_HOST: softplc_http_ha_sim.host,
        CONF_PORT: softplc_http_ha_sim.port,
        CONF_TLS: "none",
        CONF_FINGERPRINT: "",
        CONF_OPTIONS: {},
        "username": "",
        "password": "",
    }


@flow_only
async def test_same_plc_twice(hass: HomeAssistant, softplc_http_ha_sim: SoftplcSimulator) -> None:
    """The same PLC twice aborts."""
    result = await connection_form(hass)
    result = await submit(hass, result, connection(softplc_http_ha_sim))
    assert result["type"] is FlowResultType.CREATE_ENTRY
    result = await connection_form(hass)
    result = await submit(hass, result, connection(softplc_http_ha_sim))
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "already_configured"


@flow_only
async def test_https_pin_with_pasted_certificate(
    hass: HomeAssistant, softplc_ha_sim: SoftplcSimulator
) -> None:
    """HTTPS: the PLC's certificate is shown and pinned; the pasted client certificate is
    checked with an empty PUT (nothing written) and stored as PEM."""
    pair = pem_pair(softplc_ha_sim)
    result = await connection_form(hass)
    result = await submit(hass, result, connection(softplc_ha_sim, **pair))
    assert result["step_id"] == "certificate"
    placeholders = result["description_placeholders"]
    assert placeholders[CONF_FINGERPRINT] == format_fingerprint(softplc_ha_sim.fingerprint or "")
    assert placeholders[CONF_PORT] == str(softplc_ha_sim.port)
    result = await submit(hass, result, {})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["data"][CONF_TLS] == "pin"
    assert result["data"][CONF_FINGERPRINT] == softplc_ha_sim.fingerprint
    assert result["data"][CONF_OPTIONS] == {
        CERTIFICATE: pair[CERTIFICATE].strip() + "\n",
        KEY: pair[KEY].strip() + "\n",
    }
    assert softplc_ha_sim.bodies[-1].endswith(b"<files />") or softplc_ha_sim.bodies[-1].endswith(
        b"<files/>"
    )
    assert softplc_ha_sim.files["N", 7].words[:3] == [0, 1, 2]  # nothing written


@flow_only
@pytest.mark.parametrize("absolute", [False, True])
async def test_pem_paths_in_the_config_folder(
    hass: HomeAssistant, softplc_ha_sim: SoftplcSimulator, tmp_path: Path, absolute: bool
) -> None:
    """Files in the configuration folder, given relative to it or absolute, are stored as
    absolute paths (a renewed file is used without reconfiguring)."""
    hass.config.config_dir = str(tmp_path)
    (tmp_path / "softplc").mkdir()
    pair = pem_pair(softplc_ha_sim)
    paths = {CERTIFICATE: tmp_path / "softplc/client.pem", KEY: tmp_path / "softplc/client.key"}
    for option, path in paths.items():
        path.write_text(pair[option])
    given = {
        option: str(path) if absolute else str(path.relative_to(tmp_path))
        for option, path in paths.items()
    }
    result = await connection_form(hass)
    result = await submit(hass, result, connection(softplc_ha_sim, **given))
    result = await submit(hass, result, {})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["data"][CONF_OPTIONS] == {key: str(path) for key, path in paths.items()}


@flow_only
@pytest.mark.parametrize("option", [CERTIFICATE, KEY])
@pytest.mark.parametrize("path", ["/etc/ssl/private/client.pem", "../client.pem"])
async def test_paths_outside_the_config_folder(
    hass: HomeAssistant,
    softplc_ha_sim: SoftplcSimulator,
    tmp_path: Path,
    option: str,
    path: str,
) -> None:
    """A file outside the configuration folder is refused on its field, before any request."""
    hass.config.config_dir = str(tmp_path / "config")
    (tmp_path / "config").mkdir()
    (tmp_path / "client.pem").write_text(pem_pair(softplc_ha_sim)[option])
    result = await connection_form(hass)
    result = await submit(
        hass, result, connection(softplc_ha_sim, **(pem_pair(softplc_ha_sim) | {option: path}))
    )
    assert result["step_id"] == "connection_softplc"
    assert result["errors"] == {option: "pem_outside_config"}
    assert error_message(result, option, *CONFIG).startswith(
        "Home Assistant reads certificate and key files only from its configuration folder."
    )
    assert softplc_ha_sim.requests == 0
    assert suggested(result, CONF_HOST) == softplc_ha_sim.host
    assert suggested(result, CERTIFICATE) is None
    assert suggested(result, KEY) is None


def bad_pem(sim: SoftplcSimulator, case: str) -> dict[str, str]:
    """Return a certificate and key of which one cannot be used."""
    pair = pem_pair(sim)
    other = pem_pair(sim)
    garbled = "-----BEGIN {0}-----\nbm90IGEgY2VydGlmaWNhdGU=\n-----END {0}-----\n"
    return {
        "garbled certificate": pair | {CERTIFICATE: garbled.format("CERTIFICATE")},
        "key as certificate": pair | {CERTIFICATE: pair[KEY]},
        "garbled key": pair | {KEY: garbled.format("PRIVATE KEY")},
        "another certificate's key": pair | {KEY: other[KEY]},
        "certificate without key": {CERTIFICATE: pair[CERTIFICATE]},
        "key without certificate": {KEY: pair[KEY]},
        "missing file": pair | {CERTIFICATE: "softplc/nowhere.pem"},
        "certificate as key": pair | {KEY: pair[CERTIFICATE]},
        "NUL in the path": pair | {CERTIFICATE: "softplc/a\x00b.pem"},
    }[case]


@flow_only
@pytest.mark.parametrize(
    ("case", "option", "problem"),
    [
        ("garbled certificate", CERTIFICATE, "not a readable PEM certificate"),
        ("key as certificate", CERTIFICATE, "not a PEM certificate"),
        ("missing file", CERTIFICATE, "file is not in the configuration folder"),
        ("key without certificate", CERTIFICATE, "needs its certificate"),
        ("garbled key", KEY, "not the unencrypted PEM private key of that certificate"),
        ("another certificate's key", KEY, "not the unencrypted PEM private key"),
        ("certificate as key", KEY, "not a PEM private key"),
        ("certificate without key", KEY, "needs its key"),
        ("NUL in the path", CERTIFICATE, "holds a NUL character"),
        ("huge file", KEY, "larger than 256 KiB"),
    ],
)
async def test_unusable_certificate_or_key(  # noqa: PLR0917
    hass: HomeAssistant,
    softplc_ha_sim: SoftplcSimulator,
    tmp_path: Path,
    case: str,
    option: str,
    problem: str,
) -> None:
    """A certificate or key that cannot be used is refused on its own field, never quoted,
    before any request; fixing it goes on."""
    hass.config.config_dir = str(tmp_path)
    if case == "huge file":  # a usable key, padded past the size read
        given = pem_pair(softplc_ha_sim)
        (tmp_path / "huge.pem").write_text(given[KEY] + "\n" * (256 * 1024))
        given[KEY] = "huge.pem"
    else:
        given = bad_pem(softplc_ha_sim, case)
    result = await connection_form(hass)
    result = await submit(hass, result, connection(softplc_ha_sim, **given))
    assert result["errors"] == {option: "invalid_pem"}
    message = error_message(result, option, *CONFIG)
    assert message.startswith("This cannot be used: ")
    assert problem in message
    assert "BEGIN" not in message.split(". Paste")[0]
    assert "MII" not in message
    assert softplc_ha_sim.requests == 0
    result = await submit(hass, result, connection(softplc_ha_sim, **pem_pair(softplc_ha_sim)))
    assert result["step_id"] == "certificate"


@flow_only
@pytest.mark.parametrize("cert_check", ["request", "handshake"])
async def test_untrusted_certificate_on_its_field(hass: HomeAssistant, cert_check: str) -> None:
    """A certificate the PLC does not trust (refused at the PUT or in the handshake) is
    refused on the certificate field, before the entry exists."""
    sim = SoftplcSimulator(tls=True, put_auth=True, bench=0)
    sim.cert_check = cert_check
    await sim.start()
    try:
        result = await connection_form(hass)
        result = await submit(hass, result, connection(sim, **pem_pair(sim, trusted=False)))
        if result["step_id"] == "certificate":
            result = await submit(hass, result, {})
        assert result["errors"] == {CERTIFICATE: "invalid_auth"}
        assert "client certificate" in error_message(result, CERTIFICATE, *CONFIG)
        assert sim.files["N", 7].words[0] == 0
    finally:
        await sim.stop()


def certificate_entry(
    hass: HomeAssistant, sim: SoftplcSimulator, **changes: Any
) -> MockConfigEntry:
    """Add an entry of the simulator holding a (trusted, unless changed) client certificate."""
    options = {key: value.strip() + "\n" for key, value in pem_pair(sim).items()}
    return make_softplc_entry(hass, sim, [], **{CONF_OPTIONS: options | changes})


@flow_only
async def test_reconfigure_keeps_the_stored_certificate(
    hass: HomeAssistant, softplc_ha_sim: SoftplcSimulator
) -> None:
    """The certificate and key are never suggested; left empty, they stay as stored."""
    entry = certificate_entry(hass, softplc_ha_sim)
    stored = dict(entry.data[CONF_OPTIONS])
    result = translated(await entry.start_reconfigure_flow(hass), *CONFIG)
    assert result["step_id"] == "reconfigure_softplc"
    assert suggested(result, CONF_HOST) == softplc_ha_sim.host
    assert suggested(result, CERTIFICATE) is None
    assert suggested(result, KEY) is None
    assert "PRIVATE KEY" not in str(result)
    result = await submit(hass, result, connection(softplc_ha_sim))
    assert result["reason"] == "reconfigure_successful"
    assert entry.data[CONF_OPTIONS] == stored


@flow_only
async def test_reconfigure_replaces_the_certificate(
    hass: HomeAssistant, softplc_ha_sim: SoftplcSimulator
) -> None:
    """A pasted certificate and key replace the stored ones."""
    entry = certificate_entry(hass, softplc_ha_sim)
    new = pem_pair(softplc_ha_sim)
    result = await entry.start_reconfigure_flow(hass)
    result = await submit(hass, result, connection(softplc_ha_sim, **new))
    assert result["reason"] == "reconfigure_successful"
    assert entry.data[CONF_OPTIONS] == {key: value.strip() + "\n" for key, value in new.items()}


@flow_only
async def test_reconfigure_certificate_must_fit_the_stored_key(
    hass: HomeAssistant, softplc_ha_sim: SoftplcSimulator
) -> None:
    """A new certificate alone must be the stored key's: else it is refused on its field."""
    entry = certificate_entry(hass, softplc_ha_sim)
    stored = dict(entry.data[CONF_OPTIONS])
    result = await entry.start_reconfigure_flow(hass)
    new = {CERTIFICATE: pem_pair(softplc_ha_sim)[CERTIFICATE]}
    result = await submit(hass, result, connection(softplc_ha_sim, **new))
    assert result["errors"] == {CERTIFICATE: "invalid_pem"}
    assert "does not fit the stored client key" in error_message(result, CERTIFICATE, *CONFIG)
    assert suggested(result, CERTIFICATE) is None  # a secret, not suggested even now
    assert entry.data[CONF_OPTIONS] == stored


@flow_only
async def test_reauth_takes_a_new_certificate(
    hass: HomeAssistant, softplc_ha_sim: SoftplcSimulator
) -> None:
    """The refused certificate is replaced: a refused or unusable one shows on the form."""
    entry = certificate_entry(
        hass,
        softplc_ha_sim,
        **{k: v.strip() + "\n" for k, v in pem_pair(softplc_ha_sim, trusted=False).items()},
    )
    result = translated(await entry.start_reauth_flow(hass), *CONFIG)
    assert result["step_id"] == "reauth_softplc"
    assert [str(marker) for marker in result["data_schema"].schema] == [CERTIFICATE, KEY]
    assert suggested(result, CERTIFICATE) is None
    assert result["description_placeholders"] == {"name": "SoftPLC", "problem": ""}
    result = await submit(hass, result, pem_pair(softplc_ha_sim, trusted=False))
    assert result["errors"] == {CERTIFICATE: "invalid_auth"}
    assert "refused the client certificate for writes (403" in error_message(
        result, CERTIFICATE, *CONFIG
    )
    result = await submit(hass, result, bad_pem(softplc_ha_sim, "another certificate's key"))
    assert result["errors"] == {KEY: "invalid_pem"}
    new = pem_pair(softplc_ha_sim)
    result = await submit(hass, result, new)
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "reauth_successful"
    assert entry.data[CONF_OPTIONS] == {key: value.strip() + "\n" for key, value in new.items()}


@flow_only
async def test_reauth_path_outside_the_config_folder(
    hass: HomeAssistant, softplc_ha_sim: SoftplcSimulator, tmp_path: Path
) -> None:
    """The reauth form refuses a path outside the configuration folder on its field."""
    hass.config.config_dir = str(tmp_path)
    entry = certificate_entry(hass, softplc_ha_sim)
    result = await entry.start_reauth_flow(hass)
    result = await submit(hass, result, pem_pair(softplc_ha_sim) | {KEY: "/root/client.key"})
    assert result["errors"] == {KEY: "pem_outside_config"}
    assert softplc_ha_sim.requests == 0
