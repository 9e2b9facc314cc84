"""Reconfigure and reauth of entries that are really set up: the PLC stays the same device."""

from __future__ import annotations

from homeassistant.config_entries import ConfigEntryState
from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_PORT, CONF_USERNAME
from homeassistant.core import HomeAssistant
from homeassistant.helpers import device_registry as dr, entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import CONF_TLS
from simulators.s7_smart import DEFAULT_PASSWORD, DEFAULT_USER, S7SmartSimulator
from tests.entries import ENTRY_ID, edit_point, make_entry, plc_device

pytestmark = pytest.mark.no_pacing


def registered(
    entity_registry: er.EntityRegistry, device_registry: dr.DeviceRegistry, entry_id: str
) -> tuple[dict[str, str], set[str]]:
    """Return the entry's entities (entity id: unique id) and its device ids."""
    entities = {
        item.entity_id: item.unique_id
        for item in er.async_entries_for_config_entry(entity_registry, entry_id)
    }
    devices = {item.id for item in dr.async_entries_for_config_entry(device_registry, entry_id)}
    return entities, devices


async def move(hass: HomeAssistant, entry: MockConfigEntry, port: int) -> None:
    """Reconfigure the entry to the simulator's port on loopback, and wait for its reload."""
    result = await entry.start_reconfigure_flow(hass)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_HOST: "127.0.0.1", CONF_PORT: port, CONF_TLS: "pin"}
    )
    assert result["reason"] == "reconfigure_successful"
    await hass.async_block_till_done()


async def test_moving_an_address_only_plc_keeps_its_entities(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    entity_registry: er.EntityRegistry,
    device_registry: dr.DeviceRegistry,
) -> None:
    """Reconfigure to a new port: same device, same entity ids, none orphaned or doubled."""
    entry = make_entry(hass, s7_smart_ha_sim)
    hass.config_entries.async_update_entry(entry, unique_id=f"127.0.0.1:{s7_smart_ha_sim.port}")
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    before = registered(entity_registry, device_registry, entry.entry_id)
    assert len(before[0]) > 5
    assert len(before[1]) == 2  # the PLC's device and its points' device
    assert plc_device(device_registry, ENTRY_ID) is not None

    old_port = s7_smart_ha_sim.port
    await s7_smart_ha_sim.stop()
    await s7_smart_ha_sim.start()  # a free port: the PLC moved
    assert s7_smart_ha_sim.port != old_port
    await move(hass, entry, s7_smart_ha_sim.port)

    assert entry.state is ConfigEntryState.LOADED
    assert entry.unique_id == f"127.0.0.1:{s7_smart_ha_sim.port}"
    assert registered(entity_registry, device_registry, entry.entry_id) == before
    assert hass.states.get("sensor.s7_200_smart_temperature").state == "21.5"


async def test_reauth_after_a_failed_setup_loads_the_entry(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """The password was wrong at start-up: the right one sets the PLC up without a restart."""
    entry = make_entry(hass, s7_smart_ha_sim, password="wrong")
    await hass.config_entries.async_setup(entry.entry_id)
    assert entry.state is ConfigEntryState.SETUP_ERROR
    result = await entry.start_reauth_flow(hass)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_USERNAME: DEFAULT_USER, CONF_PASSWORD: DEFAULT_PASSWORD}
    )
    assert result["reason"] == "reauth_successful"
    await hass.async_block_till_done()
    assert entry.state is ConfigEntryState.LOADED
    assert hass.states.get("sensor.s7_200_smart_temperature").state == "21.5"


async def test_reconfigure_after_a_failed_setup_loads_the_entry(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """The PLC was at another port when Home Assistant started: reconfigured, it loads."""
    entry = make_entry(hass, s7_smart_ha_sim, port=1)
    await hass.config_entries.async_setup(entry.entry_id)
    assert entry.state is ConfigEntryState.SETUP_RETRY
    await move(hass, entry, s7_smart_ha_sim.port)
    assert entry.state is ConfigEntryState.LOADED


async def test_reconfigure_reloads_once(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, setups: list[str]
) -> None:
    """A reconfigure sets the PLC up again exactly once; editing points sets it up not at all."""
    entry = make_entry(hass, s7_smart_ha_sim)
    hass.config_entries.async_update_entry(entry, unique_id=f"127.0.0.1:{s7_smart_ha_sim.port}")
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    setups.clear()
    await s7_smart_ha_sim.stop()
    await s7_smart_ha_sim.start()  # on another port: the PLC moved
    await move(hass, entry, s7_smart_ha_sim.port)
    assert setups == [entry.entry_id]
    edit_point(hass, entry, "pressure", name="Pressure 2")
    await hass.async_block_till_done()
    assert setups == [entry.entry_id]
    assert entry.state is ConfigEntryState.LOADED
