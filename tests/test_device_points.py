"""Device subentries holding points: devices, edits in place (the migration: tests/model/)."""

from __future__ import annotations

from datetime import timedelta

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import ConfigEntryState, ConfigSubentry
from homeassistant.const import STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.helpers import (
    area_registry as ar,
    device_registry as dr,
    entity_registry as er,
)
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, async_fire_time_changed

from custom_components.plc_bridge.const import CONF_AREA, CONF_POINTS, DOMAIN, SUBENTRY_DEVICE
from custom_components.plc_bridge.plc import Point
from simulators.s7_smart import S7SmartSimulator
from tests.entries import (
    DEVICE_ID,
    ENTRY_ID,
    POINTS,
    edit_point,
    make_entry,
    plant_entry,
    point,
    read_edits,
    remove_point,
    set_points,
)

pytestmark = pytest.mark.no_pacing

TEMPERATURE = "sensor.s7_200_smart_temperature"
PRESSURE = "sensor.s7_200_smart_pressure"


def entry_devices(registry: dr.DeviceRegistry, entry: MockConfigEntry) -> list[dr.DeviceEntry]:
    """Return the devices of an entry."""
    return dr.async_entries_for_config_entry(registry, entry.entry_id)


async def test_adding_a_point_touches_no_other_entity(
    hass: HomeAssistant, setup_integration: MockConfigEntry, freezer: FrozenDateTimeFactory
) -> None:
    """A new point shows its value once edits pause; no reload, others keep their state."""
    entry = setup_integration
    coordinator = entry.runtime_data.coordinator
    before = hass.states.get(TEMPERATURE)
    points = dict(entry.subentries[DEVICE_ID].data[CONF_POINTS])
    points |= dict([point("level", "Level", "sensor", "VW10", "unsigned")])
    set_points(hass, entry, points)
    await hass.async_block_till_done()
    await read_edits(hass, freezer)
    assert entry.runtime_data.coordinator is coordinator
    assert hass.states.get("sensor.s7_200_smart_level").state == "235"
    after = hass.states.get(TEMPERATURE)
    assert after is not None
    assert before is not None
    assert after.last_updated == before.last_updated
    assert after.state == "21.5"


async def test_editing_a_point_keeps_its_entity(
    hass: HomeAssistant, setup_integration: MockConfigEntry, entity_registry: er.EntityRegistry
) -> None:
    """A new scale re-creates the point's entity under the same entity id; others stay."""
    entry = setup_integration
    registered = entity_registry.async_get(PRESSURE)
    assert registered is not None
    untouched = hass.states.get(TEMPERATURE)
    edit_point(hass, entry, "pressure", scale=0.01, name="Pressure")
    await hass.async_block_till_done()
    assert hass.states.get(PRESSURE).state == "2.35"
    again = entity_registry.async_get(PRESSURE)
    assert again is not None
    assert again.id == registered.id
    assert hass.states.get(TEMPERATURE) == untouched


async def test_changing_a_point_platform(
    hass: HomeAssistant, setup_integration: MockConfigEntry, entity_registry: er.EntityRegistry
) -> None:
    """Another entity type: the old entity goes, one of the new type comes."""
    edit_point(hass, setup_integration, "setpoint", platform="sensor")
    await hass.async_block_till_done()
    assert entity_registry.async_get("number.s7_200_smart_setpoint") is None
    assert hass.states.get("number.s7_200_smart_setpoint") is None
    assert hass.states.get("sensor.s7_200_smart_setpoint").state == "30"


async def test_removing_a_point(
    hass: HomeAssistant, setup_integration: MockConfigEntry, entity_registry: er.EntityRegistry
) -> None:
    """A removed point's entity leaves the state machine and the registry."""
    remove_point(hass, setup_integration, "pump")
    await hass.async_block_till_done()
    assert hass.states.get("switch.s7_200_smart_pump") is None
    assert entity_registry.async_get("switch.s7_200_smart_pump") is None
    assert setup_integration.state is ConfigEntryState.LOADED
    assert Point("Q0.0", "signed") not in setup_integration.runtime_data.coordinator.points.values()


async def test_second_device_with_an_area(
    hass: HomeAssistant,
    setup_integration: MockConfigEntry,
    device_registry: dr.DeviceRegistry,
    area_registry: ar.AreaRegistry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """A new device subentry is its own device in its area, via the PLC; removing it cleans up."""
    entry = setup_integration
    area = area_registry.async_create("Greenhouse")
    vents = ConfigSubentry(
        data={
            CONF_AREA: area.id,
            CONF_POINTS: dict([point("vent", "Vent", "switch", "Q0.1", "signed")]),
        },
        subentry_type=SUBENTRY_DEVICE,
        title="Greenhouse vents",
        unique_id=None,
    )
    hass.config_entries.async_add_subentry(entry, vents)
    await hass.async_block_till_done()
    await read_edits(hass, freezer)
    # Entity ids take the area's name too on the current release: look the entity up.
    vent = er.async_get(hass).async_get_entity_id("switch", DOMAIN, f"{ENTRY_ID}_vent")
    assert vent is not None
    assert hass.states.get(vent).state == "off"
    devices = entry_devices(device_registry, entry)
    assert len(devices) == 3
    (new,) = [d for d in devices if d.name == "Greenhouse vents"]
    assert new.area_id == area.id
    (boiler,) = [d for d in devices if (DOMAIN, DEVICE_ID) in d.identifiers]
    (plc,) = [d for d in devices if d.via_device_id is None]
    assert new.via_device_id == plc.id
    assert boiler.via_device_id == plc.id

    hass.config_entries.async_remove_subentry(entry, vents.subentry_id)
    await hass.async_block_till_done()
    assert hass.states.get(vent) is None
    assert "Greenhouse vents" not in {d.name for d in entry_devices(device_registry, entry)}
    assert hass.states.get(TEMPERATURE).state == "21.5"


async def test_points_added_one_second_apart(
    hass: HomeAssistant, setup_integration: MockConfigEntry, freezer: FrozenDateTimeFactory
) -> None:
    """Ten points added in quick succession are all available, with no reload between."""
    entry = setup_integration
    for index in range(10):
        points = dict(entry.subentries[DEVICE_ID].data[CONF_POINTS])
        points |= dict(
            [point(f"w{index}", f"Word {index}", "sensor", f"VW{400 + 2 * index}", "signed")]
        )
        set_points(hass, entry, points)
        freezer.tick(timedelta(seconds=1))
        async_fire_time_changed(hass)
        await hass.async_block_till_done()
    await read_edits(hass, freezer)
    for index in range(10):
        state = hass.states.get(f"sensor.s7_200_smart_word_{index}")
        assert state is not None
        assert state.state == "0"
    assert entry.state is ConfigEntryState.LOADED


async def test_read_only_points_of_the_coordinator(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """The coordinator knows which addresses read-only points name (writes to them are refused)."""
    points = [*POINTS, point("locked", "Locked", "sensor", "VW50", "signed", read_only=True)]
    entry = make_entry(hass, s7_smart_ha_sim, points)
    assert await hass.config_entries.async_setup(entry.entry_id)
    assert entry.runtime_data.coordinator.read_only_points == {Point("VW50", "signed")}


async def test_thousand_points_in_ten_devices(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, device_registry: dr.DeviceRegistry
) -> None:
    """1,000 points in 10 devices: every entity available, 10 + 1 devices, 32 requests a poll."""
    entry = plant_entry(hass, s7_smart_ha_sim, 10, 100)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    states = [s for s in hass.states.async_all("sensor") if s.entity_id.startswith("sensor.mach")]
    assert len(states) == 1000
    assert all(state.state != STATE_UNAVAILABLE for state in states)
    assert len(entry_devices(device_registry, entry)) == 11
    assert entry.runtime_data.client.metrics.last_poll_requests == 32


async def test_edited_area_moves_the_device(
    hass: HomeAssistant,
    setup_integration: MockConfigEntry,
    device_registry: dr.DeviceRegistry,
    area_registry: ar.AreaRegistry,
) -> None:
    """The device flow's new area moves the device; an area set in the registry stays else."""
    entry = setup_integration
    cellar, attic = area_registry.async_create("Cellar"), area_registry.async_create("Attic")
    subentry = entry.subentries[DEVICE_ID]
    (boiler,) = [
        d for d in entry_devices(device_registry, entry) if (DOMAIN, DEVICE_ID) in d.identifiers
    ]
    assert boiler.area_id is None
    hass.config_entries.async_update_subentry(
        entry, subentry, data={**subentry.data, CONF_AREA: cellar.id}
    )
    await hass.async_block_till_done()
    assert device_registry.async_get(boiler.id).area_id == cellar.id
    # The user moves it in the device registry; an edit of its points leaves it there.
    device_registry.async_update_device(boiler.id, area_id=attic.id)
    edit_point(hass, entry, "pump", name="Boiler pump")
    await hass.async_block_till_done()
    assert device_registry.async_get(boiler.id).area_id == attic.id
