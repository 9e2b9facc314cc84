"""Diagnostics of a SoftPLC: the client certificate and its key never leave Home Assistant."""

from __future__ import annotations

from pathlib import Path

from freezegun.api import FrozenDateTimeFactory
from homeassistant.core import HomeAssistant
import pytest
from pytest_homeassistant_custom_component.components.diagnostics import (
    get_diagnostics_for_config_entry,
)
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator

from custom_components.plc_bridge.const import CONF_OPTIONS
from simulators.softplc import SoftplcSimulator
from tests.entries import poll
from tests.harness import make_softplc_entry, pem_pair

REDACTED = "**REDACTED**"


@pytest.mark.parametrize("as_files", [False, True])
async def test_certificate_and_key_redacted(  # noqa: PLR0917
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    softplc_ha_sim: SoftplcSimulator,
    freezer: FrozenDateTimeFactory,
    tmp_path: Path,
    as_files: bool,
) -> None:
    """Pasted PEM or file paths: both are redacted; the poll's figures are there."""
    pair = pem_pair(softplc_ha_sim)
    options = {key: value.strip() + "\n" for key, value in pair.items()}
    if as_files:
        for key, value in pair.items():
            (tmp_path / key).write_text(value)
        options = {key: str(tmp_path / key) for key in pair}
    entry = make_softplc_entry(hass, softplc_ha_sim, **{CONF_OPTIONS: options})
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    await poll(hass, freezer)
    result = await get_diagnostics_for_config_entry(hass, hass_client, entry)
    assert result["entry"]["data"][CONF_OPTIONS] == {
        "client_certificate": REDACTED,
        "client_key": REDACTED,
    }
    assert result["device"]["extra"] == {"writes_with_certificate": "yes"}
    assert result["poll"]["planned_requests"] == 1
    assert result["results"]["F8:0|REAL"] == {"ok": True, "value": 21.5}
    assert result["results"]["important_int|INT"] == {"ok": True, "value": 10}
    text = str(result)
    for secret in (*pair.values(), str(tmp_path), softplc_ha_sim.fingerprint or "", "127.0.0.1"):
        assert secret not in text
    for line in (*pair["client_certificate"].splitlines(), *pair["client_key"].splitlines()):
        if "-----" not in line:
            assert line not in text
