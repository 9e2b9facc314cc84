"""Tests of the diagnostics: content, with credentials and the PLC's whereabouts redacted."""

from __future__ import annotations

from homeassistant.core import HomeAssistant
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
from pytest_homeassistant_custom_component.components.diagnostics import (
    get_diagnostics_for_config_entry,
)
from pytest_homeassistant_custom_component.typing import ClientSessionGenerator
from syrupy.assertion import SnapshotAssertion
from syrupy.filters import props

from simulators.s7_smart import DEFAULT_PASSWORD, S7SmartSimulator

pytestmark = pytest.mark.no_pacing


async def test_diagnostics(
    hass: HomeAssistant,
    hass_client: ClientSessionGenerator,
    s7_smart_ha_sim: S7SmartSimulator,
    setup_integration: MockConfigEntry,
    snapshot: SnapshotAssertion,
) -> None:
    # The title as the config flow makes it ("<model> (<host>)"); the entry reloads.
    hass.config_entries.async_update_entry(setup_integration, title="S7-200 SMART (127.0.0.1)")
    await hass.async_block_till_done()
    s7_smart_ha_sim.v_size = 150  # VB200 and VD300 fail in the next poll
    await setup_integration.runtime_data.coordinator.async_refresh()
    result = await get_diagnostics_for_config_entry(hass, hass_client, setup_integration)
    assert result == snapshot(exclude=props("port", "last_poll_ms"))
    text = str(result)
    for secret in (DEFAULT_PASSWORD, s7_smart_ha_sim.fingerprint, "127.0.0.1"):
        assert secret not in text
