"""A PLC's entry is titled as the user names its device; never like the integration."""

from __future__ import annotations

from homeassistant.core import HomeAssistant
from homeassistant.helpers import device_registry as dr
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import DOMAIN
from custom_components.plc_bridge.entity import device_key
from custom_components.plc_bridge.flows.base import entry_title
from custom_components.plc_bridge.plc import DeviceInfo
from tests.entries import UNIQUE_ID, set_up, unload_all
from tests.test_config_file import export

pytestmark = pytest.mark.no_pacing


@pytest.mark.parametrize(
    ("name", "title"),
    [
        ("Press 4", "Press 4"),
        (None, "S7-200 SMART 192.0.2.7"),
        ("  ", "S7-200 SMART 192.0.2.7"),
        ("PLC Bridge", "S7-200 SMART 192.0.2.7"),  # a station name some CPUs report
        ("plc bridge", "S7-200 SMART 192.0.2.7"),
    ],
)
def test_new_entry_title(name: str | None, title: str) -> None:
    """The PLC's own name, else its model and host: two PLCs of a model are told apart."""
    device = DeviceInfo(vendor="s7_smart", model="S7-200 SMART", name=name)
    assert entry_title(device, "192.0.2.7") == title


def plc_device_entry(hass: HomeAssistant, entry: MockConfigEntry) -> dr.DeviceEntry:
    """Return the PLC's own device."""
    registry = dr.async_get(hass)
    (device,) = [
        dev
        for dev in dr.async_entries_for_config_entry(registry, entry.entry_id)
        if (DOMAIN, device_key(entry)) in dev.identifiers
    ]
    return device


async def test_title_follows_device_name(
    hass: HomeAssistant, s7_smart_entry: MockConfigEntry
) -> None:
    """The name chosen in Home Assistant's dialog, and each rename after, titles the entry, the
    PLC's device and the exported file; clearing the name keeps the last one."""
    await set_up(hass, s7_smart_entry)
    registry = dr.async_get(hass)
    device = plc_device_entry(hass, s7_smart_entry)
    registry.async_update_device(device.id, name_by_user="Boiler house")
    await hass.async_block_till_done()
    assert s7_smart_entry.title == "Boiler house"
    assert plc_device_entry(hass, s7_smart_entry).name == "Boiler house"
    assert "title: Boiler house" in await export(hass, s7_smart_entry)
    registry.async_update_device(device.id, name_by_user="Boiler room")
    await hass.async_block_till_done()
    assert s7_smart_entry.title == "Boiler room"
    registry.async_update_device(device.id, name_by_user=None)
    await hass.async_block_till_done()
    assert s7_smart_entry.title == "Boiler room"
    registry.async_update_device(device.id, area_id=None, name="Other")  # not the user's name
    await hass.async_block_till_done()
    assert s7_smart_entry.title == "Boiler room"


async def test_rename_while_unloaded_followed_at_setup(
    hass: HomeAssistant, s7_smart_entry: MockConfigEntry
) -> None:
    """A device renamed while its entry was not loaded gives the entry its name at setup."""
    await set_up(hass, s7_smart_entry)
    device = plc_device_entry(hass, s7_smart_entry)
    await unload_all(hass)
    dr.async_get(hass).async_update_device(device.id, name_by_user="Press hall")
    await hass.async_block_till_done()
    assert s7_smart_entry.title == "S7-200 SMART"
    await set_up(hass, s7_smart_entry)
    assert s7_smart_entry.title == "Press hall"
    assert s7_smart_entry.unique_id == UNIQUE_ID
