"""Keep-alive: a set-up PLC reuses one connection across polls, whatever the poll interval."""

from __future__ import annotations

from datetime import timedelta

from freezegun.api import FrozenDateTimeFactory
from homeassistant.const import CONF_SCAN_INTERVAL
from homeassistant.core import HomeAssistant
import pytest
from pytest_homeassistant_custom_component.common import async_fire_time_changed

from custom_components.plc_bridge.plc.http import KEEPALIVE_MARGIN, KEEPALIVE_MAX
from simulators.s7_smart import S7SmartSimulator
from tests.entries import make_entry

pytestmark = pytest.mark.no_pacing


async def polls(hass: HomeAssistant, freezer: FrozenDateTimeFactory, interval: float) -> None:
    """Let ten poll intervals pass, one poll each."""
    for _ in range(10):
        freezer.tick(timedelta(seconds=interval))
        async_fire_time_changed(hass)
        await hass.async_block_till_done(wait_background_tasks=True)


@pytest.mark.parametrize("interval", [5.0, 60.0, 300.0])
async def test_one_connection_for_ten_polls(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    interval: float,
) -> None:
    """Ten polls `interval` apart: the connection of the setup serves them all (one handshake).

    Home Assistant's shared session would drop it after 15 s idle: one TLS handshake a poll.
    """
    entry = make_entry(hass, s7_smart_ha_sim)
    hass.config_entries.async_update_entry(entry, options={CONF_SCAN_INTERVAL: interval})
    assert await hass.config_entries.async_setup(entry.entry_id)
    assert len(s7_smart_ha_sim.peers) == 1
    before = s7_smart_ha_sim.calls["read"]
    await polls(hass, freezer, interval)
    assert s7_smart_ha_sim.calls["read"] - before == 10
    assert len(s7_smart_ha_sim.peers) == 1
    connector = entry.runtime_data.client.session.connector
    assert connector is not None
    assert connector._keepalive_timeout == min(interval + KEEPALIVE_MARGIN, KEEPALIVE_MAX)


async def test_session_closed_with_the_entry(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """Unloading the PLC logs out, then closes its own session (nothing left open)."""
    entry = make_entry(hass, s7_smart_ha_sim)
    assert await hass.config_entries.async_setup(entry.entry_id)
    session = entry.runtime_data.client.session
    assert await hass.config_entries.async_unload(entry.entry_id)
    assert session.closed
    assert s7_smart_ha_sim.calls["logout"] == 1
