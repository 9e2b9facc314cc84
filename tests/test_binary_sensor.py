"""Tests of the binary sensors."""

from __future__ import annotations

from freezegun.api import FrozenDateTimeFactory
from homeassistant.const import STATE_OFF, STATE_ON, Platform
from homeassistant.core import HomeAssistant
from homeassistant.helpers import entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, snapshot_platform
from syrupy.assertion import SnapshotAssertion

from simulators.s7_smart import S7SmartSimulator
from tests.conftest import current_release_only
from tests.entries import poll

pytestmark = pytest.mark.no_pacing


@pytest.fixture
def platforms() -> list[Platform]:
    """Only the binary sensor platform."""
    return [Platform.BINARY_SENSOR]


@current_release_only
async def test_snapshot(
    hass: HomeAssistant,
    setup_integration: MockConfigEntry,
    entity_registry: er.EntityRegistry,
    snapshot: SnapshotAssertion,
) -> None:
    await snapshot_platform(hass, entity_registry, snapshot, setup_integration.entry_id)


async def test_follows_the_input(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    setup_integration: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    assert hass.states.get("binary_sensor.s7_200_smart_door").state == STATE_ON
    s7_smart_ha_sim.set("I0.0", False)
    await poll(hass, freezer)
    assert hass.states.get("binary_sensor.s7_200_smart_door").state == STATE_OFF
