"""The objects a point entity keeps do not grow back: bench.objects' count, at a small size."""

from __future__ import annotations

from freezegun.api import FrozenDateTimeFactory
from homeassistant.core import HomeAssistant
import pytest

from bench.objects import OURS, count_objects, count_owners, machines, point_entities
from simulators.s7_smart import S7SmartSimulator
from tests.entries import ENTRY_ID, UNIQUE_ID, add_entry, poll, set_up, sim_data

pytestmark = pytest.mark.no_pacing

ENTITIES = 80
"""Ten of each kind bench.objects mixes."""
OURS_KEPT = 7.4
"""Objects per point entity our code keeps, at ENTITIES: the entity, what it sets on it, its
removal callbacks and its coordinator listener (14.1 while each entity had a listener of its
own: a remover partial with its arguments in `_on_remove`, a callback and a tuple in the
coordinator)."""
ALL_KEPT = 62.6
"""Objects per point entity with what Home Assistant keeps for it, its State included (69.3
with a listener per entity)."""


async def test_objects_per_point_entity(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """What our code keeps per entity, and all kept per entity, stay within a quarter above."""
    entry = add_entry(
        hass,
        title="S7-200 SMART",
        entry_id=ENTRY_ID,
        unique_id=UNIQUE_ID,
        data=sim_data(s7_smart_ha_sim),
        subentries=machines(ENTITIES),
    )
    await set_up(hass, entry)
    await poll(hass, freezer)
    coordinator = entry.runtime_data.coordinator
    shared = [entry.subentries, coordinator.data]
    counted = count_objects(hass, point_entities(hass), shared)
    assert counted["entities"] == ENTITIES
    owners = count_owners(hass, point_entities(hass), [coordinator], shared)
    ours = sum(row["objects_per_entity"] for row in owners if row["kept_by"] == OURS)
    kept = sum(row["objects_per_entity"] for row in owners)
    assert ours <= OURS_KEPT * 1.25, owners
    assert kept <= ALL_KEPT * 1.25, owners


async def test_entities_keep_no_listener_of_their_own(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """The coordinator updates its entities through one listener: none keeps a remover."""
    entry = add_entry(
        hass,
        title="S7-200 SMART",
        entry_id=ENTRY_ID,
        unique_id=UNIQUE_ID,
        data=sim_data(s7_smart_ha_sim),
        subentries=machines(ENTITIES),
    )
    await set_up(hass, entry)
    coordinator = entry.runtime_data.coordinator
    assert len(coordinator._listeners) == 1
    assert all(
        "remove_listener_internal" not in str(getattr(callback, "func", callback))
        for entity in point_entities(hass)
        for callback in entity._on_remove or ()
    )
    assert await hass.config_entries.async_unload(entry.entry_id)
    assert not coordinator._listeners


async def test_an_entity_whose_add_was_aborted_is_no_longer_updated(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """Home Assistant aborting an add after the entity followed: the next update drops it."""
    entry = add_entry(
        hass,
        title="S7-200 SMART",
        entry_id=ENTRY_ID,
        unique_id=UNIQUE_ID,
        data=sim_data(s7_smart_ha_sim),
        subentries=machines(8),
    )
    await set_up(hass, entry)
    coordinator = entry.runtime_data.coordinator
    aborted, *others = point_entities(hass)
    aborted.add_to_platform_abort()
    coordinator._changed = None  # update every entity
    coordinator.async_set_updated_data(coordinator.data)
    assert "Unexpected error" not in caplog.text
    assert aborted not in coordinator._followers
    assert all(entity in coordinator._followers for entity in others)
