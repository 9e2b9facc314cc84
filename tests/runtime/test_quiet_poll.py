"""A poll where nothing changed writes no entity state; a changed point writes its own only."""

from __future__ import annotations

from unittest.mock import patch

from freezegun.api import FrozenDateTimeFactory
from homeassistant.core import HomeAssistant
from homeassistant.helpers import entity_registry as er
from homeassistant.helpers.entity import Entity
import pytest

from simulators.s7_smart import S7SmartSimulator
from tests.entries import make_entry, point, poll

pytestmark = pytest.mark.no_pacing


async def test_quiet_poll_writes_nothing(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    points = [point(f"p{i}", f"Point {i}", "sensor", f"VW{2 * i}", "signed") for i in range(5)]
    points.append(point("flag", "Flag", "binary_sensor", "V100.0", "signed"))
    entry = make_entry(hass, s7_smart_ha_sim, points)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    await poll(hass, freezer)
    ours = {
        e.entity_id: e.unique_id.rsplit("_", 1)[-1]
        for e in er.async_entries_for_config_entry(er.async_get(hass), entry.entry_id)
        if e.config_subentry_id is not None
    }
    writes: list[str] = []
    original = Entity.async_write_ha_state

    def counting(entity: Entity) -> None:
        writes.append(entity.entity_id)
        original(entity)

    with patch.object(Entity, "async_write_ha_state", counting):
        await poll(hass, freezer, 3)
        assert writes == []
        s7_smart_ha_sim.set("VW4", 1234)
        await poll(hass, freezer)
    assert [ours[entity_id] for entity_id in writes] == ["p2"]
    assert hass.states.get(writes[0]).state == "1234"
