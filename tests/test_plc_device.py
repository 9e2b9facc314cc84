"""The PLC's own device: a link to its web page, and keys that outlive a firmware update."""

from __future__ import annotations

from homeassistant.const import CONF_HOST, CONF_PORT
from homeassistant.core import HomeAssistant
from homeassistant.helpers import device_registry as dr, entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import DOMAIN
from simulators.tecomat import TecomatSimulator
from tests.entries import ENTRY_ID, plc_device
from tests.harness import TECOMAT_ENTRY_ID, make_tecomat_entry

pytestmark = pytest.mark.no_pacing


async def test_link_to_the_plc_web_page(
    hass: HomeAssistant, setup_integration: MockConfigEntry, device_registry: dr.DeviceRegistry
) -> None:
    """The PLC's device links to the web server Home Assistant talks to (HTTPS here)."""
    device = plc_device(device_registry, ENTRY_ID)
    assert device is not None
    port = setup_integration.data[CONF_PORT]
    assert device.configuration_url == f"https://{setup_integration.data[CONF_HOST]}:{port}/"


async def test_a_serial_reported_later_re_keys_nothing(
    hass: HomeAssistant, tecomat_ha_sim: TecomatSimulator, entity_registry: er.EntityRegistry
) -> None:
    """An entry made by address (no serial then) keeps its keys when the PLC reports one."""
    entry = make_tecomat_entry(hass, tecomat_ha_sim)
    address = f"{entry.data[CONF_HOST]}:{entry.data[CONF_PORT]}"
    hass.config_entries.async_update_entry(entry, unique_id=address)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert entry.runtime_data.device.serial  # this firmware reports one
    keys = [e.unique_id for e in er.async_entries_for_config_entry(entity_registry, entry.entry_id)]
    assert keys
    assert all(key.startswith(f"{TECOMAT_ENTRY_ID}_") for key in keys), keys
    devices = dr.async_entries_for_config_entry(dr.async_get(hass), entry.entry_id)
    device = next((d for d in devices if (DOMAIN, TECOMAT_ENTRY_ID) in d.identifiers), None)
    assert device is not None
    assert device.configuration_url == f"http://{address}/"  # plain HTTP: no TLS
