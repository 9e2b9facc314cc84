"""Installations upgrade with nothing to do: stored entries of 0.1 and 0.9 load as they were.

tests/fixtures/entry_0_1.json is an entry as the first released build stored it (version 1.1,
one point per subentry, the PLC keyed by host:port); entry_0_9.json one made by 0.9's flows with
a machine of every kind and an expose. Each is stored with its entity registry as that build left
it, and the states Home Assistant restores; after setup every entity keeps its registry entry,
its entity id (so its history) and its restored state, and nothing is registered twice.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from homeassistant.config_entries import ConfigEntryState, ConfigSubentryDataWithId
from homeassistant.core import HomeAssistant, State
from homeassistant.helpers import device_registry as dr, entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import (
    MockConfigEntry,
    mock_restore_cache_with_extra_data,
)

from custom_components.plc_bridge.config_flow import PlcBridgeConfigFlow
from custom_components.plc_bridge.const import CONF_POINTS, DOMAIN, SUBENTRY_DEVICE
from simulators.s7_smart import DEFAULT_PASSWORD, DEFAULT_USER, S7SmartSimulator
from tests.entries import ENTRY_ID, POINTS, UNIQUE_ID, add_entry, legacy_point, sim_data
from tests.test_snapshots import VALUES

pytestmark = pytest.mark.no_pacing

FIXTURES = Path(__file__).parents[1] / "fixtures"


def stored(name: str, sim: S7SmartSimulator) -> dict[str, Any]:
    """Return a stored entry of the fixtures, on the simulator's port with its secrets."""
    text = (FIXTURES / name).read_text(encoding="utf-8")
    text = text.replace('"<port>"', str(sim.port)).replace("<port>", str(sim.port))
    for field, value in (
        ("<fingerprint>", sim.fingerprint),
        ("<username>", DEFAULT_USER),
        ("<password>", DEFAULT_PASSWORD),
    ):
        text = text.replace(field, value)
    stored_entry: dict[str, Any] = json.loads(text)
    return stored_entry


def add_stored(
    hass: HomeAssistant,
    old: dict[str, Any],
    entity_registry: er.EntityRegistry,
    device_registry: dr.DeviceRegistry,
) -> MockConfigEntry:
    """Add the stored entry, its PLC's device and its entities as the old build left them."""
    entry = MockConfigEntry(
        domain=DOMAIN,
        entry_id=old["entry_id"],
        title=old["title"],
        unique_id=old["unique_id"],
        data=old["data"],
        options=old["options"],
        version=old["version"],
        minor_version=old["minor_version"],
        subentries_data=[ConfigSubentryDataWithId(**subentry) for subentry in old["subentries"]],
    )
    entry.add_to_hass(hass)
    plc = device_registry.async_get_or_create(
        config_entry_id=entry.entry_id,
        identifiers={(DOMAIN, old["device"]["identifier"])},
        name=old["device"]["name"],
        model=old["device"]["model"],
    )
    for entity in old["entities"]:
        platform, object_id = entity["entity_id"].split(".")
        registered = entity_registry.async_get_or_create(
            platform,
            DOMAIN,
            entity["unique_id"],
            config_entry=entry,
            config_subentry_id=entity["config_subentry_id"],
            device_id=plc.id,
            suggested_object_id=object_id,
            original_name=entity["original_name"],
        )
        assert registered.entity_id == entity["entity_id"]
    return entry


async def upgraded(
    hass: HomeAssistant,
    old: dict[str, Any],
    entity_registry: er.EntityRegistry,
    device_registry: dr.DeviceRegistry,
) -> tuple[MockConfigEntry, dict[str, str]]:
    """Store the old entry, set it up; return it and each old entity's registry entry id."""
    mock_restore_cache_with_extra_data(
        hass,
        [
            (State(item["entity_id"], item["state"], item.get("attributes")), item.get("extra", {}))
            for item in old["restored"]
        ],
    )
    entry = add_stored(hass, old, entity_registry, device_registry)
    before = {e["entity_id"]: entity_registry.async_get(e["entity_id"]).id for e in old["entities"]}
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert entry.state is ConfigEntryState.LOADED
    assert (entry.version, entry.minor_version) == (
        PlcBridgeConfigFlow.VERSION,
        PlcBridgeConfigFlow.MINOR_VERSION,
    )
    return entry, before


def kept(
    hass: HomeAssistant, entry: MockConfigEntry, before: dict[str, str], key: str
) -> dict[str, str]:
    """Check each old entity is the same registry entry, keyed as before, and shown.

    Returns every entity id of the entry after the upgrade by its unique id; `key` is what the
    entities' unique ids start with now.
    """
    registry = er.async_get(hass)
    now = er.async_entries_for_config_entry(registry, entry.entry_id)
    by_unique_id = {registered.unique_id: registered.entity_id for registered in now}
    assert len(by_unique_id) == len(now)
    for entity_id, registry_id in before.items():
        registered = registry.async_get(entity_id)
        assert registered is not None, entity_id
        assert registered.id == registry_id, f"{entity_id} was registered anew"
        assert registered.unique_id.startswith(f"{key}_"), registered.unique_id
        state = hass.states.get(entity_id)
        assert state is not None, entity_id
    assert not [e.entity_id for e in now if e.entity_id.rsplit("_", 1)[-1].isdigit()]
    return by_unique_id


async def test_upgrade_from_0_1(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    entity_registry: er.EntityRegistry,
    device_registry: dr.DeviceRegistry,
) -> None:
    """The first release's entry: its points move into a machine, every entity stays itself.

    That build keyed a PLC without serial or MAC by host:port, later builds by the entry (a
    PLC moved with Reconfigure keeps its entities): the migration re-keys the old entities,
    which keep their registry entries, entity ids and so their history.
    """
    old = stored("entry_0_1.json", s7_smart_ha_sim)
    entry, before = await upgraded(hass, old, entity_registry, device_registry)
    kept(hass, entry, before, entry.entry_id)
    (machine,) = entry.subentries.values()
    assert machine.subentry_type == SUBENTRY_DEVICE
    assert set(machine.data[CONF_POINTS]) == {s["subentry_id"] for s in old["subentries"]}
    assert hass.states.get("sensor.s7_200_smart_127_0_0_1_temperature").state == "21.5"
    assert hass.states.get("number.s7_200_smart_127_0_0_1_setpoint").state == "30"
    plcs = [d for d in dr.async_entries_for_config_entry(device_registry, entry.entry_id)]
    identified = {identifier for d in plcs for _, identifier in d.identifiers}
    assert entry.entry_id in identified
    assert entry.unique_id not in identified  # the old device was re-keyed, not left beside


async def test_upgrade_from_0_9(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    entity_registry: er.EntityRegistry,
    device_registry: dr.DeviceRegistry,
) -> None:
    """0.9's entry of every kind loads as stored: same shape, entities, restored states."""
    for address, value in VALUES.items():
        s7_smart_ha_sim.set(address, value)
    old = stored("entry_0_9.json", s7_smart_ha_sim)
    entry, before = await upgraded(hass, old, entity_registry, device_registry)
    now = kept(hass, entry, before, entry.entry_id)
    assert set(now.values()) == set(before)  # nothing new, nothing gone
    assert dict(entry.data) == old["data"]
    assert dict(entry.options) == old["options"]
    assert {
        s.subentry_id: (s.subentry_type, s.title, s.unique_id, dict(s.data))
        for s in entry.subentries.values()
    } == {
        s["subentry_id"]: (s["subentry_type"], s["title"], s["unique_id"], s["data"])
        for s in old["subentries"]
    }
    for item in old["restored"]:
        assert hass.states.get(item["entity_id"]).state == item["state"], item["entity_id"]
    assert hass.states.get("event.plant_alarms").attributes["event_type"] == "Overheat"
    assert hass.states.get("cover.plant_shutter").attributes["current_position"] == 50


def legacy_entry(hass: HomeAssistant, sim: S7SmartSimulator) -> MockConfigEntry:
    """Add an entry stored as version 1 did: one point per subentry, the PLC's device shared."""
    return add_entry(
        hass,
        title="S7-200 SMART",
        entry_id=ENTRY_ID,
        unique_id=UNIQUE_ID,
        data=sim_data(sim),
        subentries=[legacy_point(item) for item in POINTS],
        version=1,
    )


async def test_migration_keeps_entities(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    entity_registry: er.EntityRegistry,
    device_registry: dr.DeviceRegistry,
) -> None:
    """Version 1 points move into one device: unique ids, entity ids and names unchanged."""
    entry = legacy_entry(hass, s7_smart_ha_sim)
    plc = device_registry.async_get_or_create(
        config_entry_id=entry.entry_id, identifiers={(DOMAIN, ENTRY_ID)}, name="S7-200 SMART"
    )
    stored: dict[str, Any] = {}
    for point_id, data in POINTS:
        platform = data["platform"]
        registered = entity_registry.async_get_or_create(
            platform,
            DOMAIN,
            f"{ENTRY_ID}_{point_id}",
            config_entry=entry,
            config_subentry_id=point_id,
            device_id=plc.id,
            suggested_object_id=f"my_{point_id}",
            original_name=data["name"],
        )
        stored[registered.entity_id] = registered.unique_id
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    assert entry.version == 2
    (device,) = entry.subentries.values()
    assert device.subentry_type == SUBENTRY_DEVICE
    assert device.title == "S7-200 SMART points"  # told apart from the PLC's own device
    assert set(device.data[CONF_POINTS]) == {point_id for point_id, _ in POINTS}
    for entity_id, unique_id in stored.items():
        registered = entity_registry.async_get(entity_id)
        assert registered is not None, entity_id
        assert registered.unique_id == unique_id
        assert registered.config_subentry_id == device.subentry_id
        assert hass.states.get(entity_id) is not None
    assert hass.states.get("sensor.my_temperature").state == "21.5"
    assert hass.states.get("sensor.my_temperature").name == "S7-200 SMART points Temperature"
    names = [d.name for d in dr.async_entries_for_config_entry(dr.async_get(hass), entry.entry_id)]
    assert sorted(names) == ["S7-200 SMART", "S7-200 SMART points"]
    assert device_registry.async_get(plc.id) is not None


async def test_newer_version_is_refused(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """An entry from a newer release is not set up (and not changed)."""
    entry = add_entry(
        hass,
        title="x",
        entry_id=ENTRY_ID,
        unique_id=UNIQUE_ID,
        data=sim_data(s7_smart_ha_sim),
        points=[],
    )
    hass.config_entries.async_update_entry(entry, version=3)
    assert not await hass.config_entries.async_setup(entry.entry_id)
    assert entry.state is ConfigEntryState.MIGRATION_ERROR
