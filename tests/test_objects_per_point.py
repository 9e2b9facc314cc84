"""The objects a point entity keeps do not grow back: bench.objects' count, at a small size."""

from __future__ import annotations

from freezegun.api import FrozenDateTimeFactory
from homeassistant.core import HomeAssistant
import pytest

from bench.objects import count_objects, machines, point_entities
from simulators.s7_smart import S7SmartSimulator
from tests.entries import ENTRY_ID, UNIQUE_ID, add_entry, poll, set_up, sim_data

pytestmark = pytest.mark.no_pacing

ENTITIES = 80
"""Ten of each kind bench.objects mixes."""
OURS = 6.9
"""Objects per point entity of the entity and what our code sets on it, at ENTITIES (14.9 before
points, conversions, labels and device info were shared)."""
BOUND = OURS * 1.25


async def test_objects_per_point_entity(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """The entity and what our code sets on it stay within a quarter above today's count."""
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
    shared = [entry.subentries, entry.runtime_data.coordinator.data]
    counted = count_objects(hass, point_entities(hass), shared)
    assert counted["entities"] == ENTITIES
    assert counted["ours_per_entity"] <= BOUND, counted
