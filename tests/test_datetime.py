"""Tests of the date and time entities: a clock point, and the clock the PLC reports."""

from __future__ import annotations

from datetime import UTC, datetime

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.datetime import (
    ATTR_DATETIME,
    DOMAIN as DATETIME_DOMAIN,
    SERVICE_SET_VALUE,
)
from homeassistant.const import ATTR_ENTITY_ID, Platform
from homeassistant.core import HomeAssistant
from homeassistant.helpers import entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, snapshot_platform
from syrupy.assertion import SnapshotAssertion

from simulators.s7_smart import S7SmartSimulator
from tests.conftest import current_release_only
from tests.entries import poll

pytestmark = pytest.mark.no_pacing

CLOCK = "datetime.s7_200_smart_clock"


@pytest.fixture
def platforms() -> list[Platform]:
    """Only the datetime platform."""
    return [Platform.DATETIME]


@current_release_only
@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_snapshot(
    hass: HomeAssistant,
    setup_integration: MockConfigEntry,
    entity_registry: er.EntityRegistry,
    snapshot: SnapshotAssertion,
) -> None:
    await snapshot_platform(hass, entity_registry, snapshot, setup_integration.entry_id)


async def test_set_clock_point(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, setup_integration: MockConfigEntry
) -> None:
    """The value is written in the PLC's local time (Home Assistant's zone: US/Pacific)."""
    await hass.services.async_call(
        DATETIME_DOMAIN,
        SERVICE_SET_VALUE,
        {ATTR_ENTITY_ID: CLOCK, ATTR_DATETIME: datetime(2026, 7, 4, 18, 0, tzinfo=UTC)},
        blocking=True,
    )
    assert s7_smart_ha_sim.clock == datetime(2026, 7, 4, 11, 0)
    assert hass.states.get(CLOCK).state == "2026-07-04T18:00:00+00:00"


@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_plc_clock_entity(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    setup_integration: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """The clock the PLC reports with its values: shown, set through it, followed at each poll."""
    plc_clock = "datetime.s7_200_smart_plc_clock"
    assert hass.states.get(plc_clock).state == "2026-03-01T20:30:00+00:00"
    await hass.services.async_call(
        DATETIME_DOMAIN,
        SERVICE_SET_VALUE,
        {ATTR_ENTITY_ID: plc_clock, ATTR_DATETIME: datetime(2026, 7, 4, 18, 0, tzinfo=UTC)},
        blocking=True,
    )
    assert s7_smart_ha_sim.clock == datetime(2026, 7, 4, 11, 0)
    assert hass.states.get(plc_clock).state == "2026-07-04T18:00:00+00:00"
    s7_smart_ha_sim.clock = datetime(2026, 7, 4, 11, 5)
    await poll(hass, freezer)
    assert hass.states.get(plc_clock).state == "2026-07-04T18:05:00+00:00"
