"""Tests of the switches: writes, the PLC in STOP, read-only points."""

from __future__ import annotations

from homeassistant.components.switch import DOMAIN as SWITCH_DOMAIN
from homeassistant.const import (
    ATTR_ENTITY_ID,
    SERVICE_TURN_OFF,
    SERVICE_TURN_ON,
    STATE_ON,
    Platform,
)
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import HomeAssistantError, ServiceValidationError
from homeassistant.helpers import entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, snapshot_platform
from syrupy.assertion import SnapshotAssertion

from simulators.s7_smart import S7SmartSimulator
from tests.conftest import current_release_only
from tests.entries import make_entry, point

pytestmark = pytest.mark.no_pacing

PUMP = "switch.s7_200_smart_pump"


@pytest.fixture
def platforms() -> list[Platform]:
    """Only the switch platform."""
    return [Platform.SWITCH]


@current_release_only
async def test_snapshot(
    hass: HomeAssistant,
    setup_integration: MockConfigEntry,
    entity_registry: er.EntityRegistry,
    snapshot: SnapshotAssertion,
) -> None:
    await snapshot_platform(hass, entity_registry, snapshot, setup_integration.entry_id)


async def test_turn_on_and_off(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, setup_integration: MockConfigEntry
) -> None:
    await hass.services.async_call(
        SWITCH_DOMAIN, SERVICE_TURN_ON, {ATTR_ENTITY_ID: PUMP}, blocking=True
    )
    assert s7_smart_ha_sim.get("Q0.0") is True
    assert hass.states.get(PUMP).state == STATE_ON

    await hass.services.async_call(
        SWITCH_DOMAIN, SERVICE_TURN_OFF, {ATTR_ENTITY_ID: PUMP}, blocking=True
    )
    assert s7_smart_ha_sim.get("Q0.0") is False
    assert s7_smart_ha_sim.calls["write"] == 2


async def test_plc_in_stop(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, setup_integration: MockConfigEntry
) -> None:
    s7_smart_ha_sim.mode = "STOP"
    with pytest.raises(HomeAssistantError) as err:
        await hass.services.async_call(
            SWITCH_DOMAIN, SERVICE_TURN_ON, {ATTR_ENTITY_ID: PUMP}, blocking=True
        )
    assert str(err.value) == (
        "The PLC refused the write: the PLC is in STOP; S7-200 SMART accepts writes only in RUN"
        " (CPU not in RUN., code 2001)"
    )
    assert err.value.translation_key == "write_refused"
    assert s7_smart_ha_sim.get("Q0.0") is False


async def test_integer_point_and_read_only(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """A byte used as a switch is written 1 and 0; a read-only point is never written."""
    entry = make_entry(
        hass,
        s7_smart_ha_sim,
        [
            point("mode", "Mode", "switch", "VB50", "unsigned"),
            point("lamp", "Lamp", "switch", "Q0.1", "signed", read_only=True),
        ],
    )
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.services.async_call(
        SWITCH_DOMAIN, SERVICE_TURN_ON, {ATTR_ENTITY_ID: "switch.s7_200_smart_mode"}, blocking=True
    )
    assert s7_smart_ha_sim.get("VB50", "unsigned") == 1

    with pytest.raises(ServiceValidationError) as err:
        await hass.services.async_call(
            SWITCH_DOMAIN,
            SERVICE_TURN_ON,
            {ATTR_ENTITY_ID: "switch.s7_200_smart_lamp"},
            blocking=True,
        )
    assert str(err.value) == "Q0.1 is a read-only point; nothing was sent"
    assert s7_smart_ha_sim.calls["write"] == 1
