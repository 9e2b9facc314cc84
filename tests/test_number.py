"""Tests of the numbers: scaled writes, and values refused before anything is sent."""

from __future__ import annotations

from homeassistant.components.number import (
    ATTR_VALUE,
    DOMAIN as NUMBER_DOMAIN,
    SERVICE_SET_VALUE,
)
from homeassistant.const import ATTR_ENTITY_ID, Platform
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import ServiceValidationError
from homeassistant.helpers import entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, snapshot_platform
from syrupy.assertion import SnapshotAssertion

from simulators.s7_smart import S7SmartSimulator
from tests.conftest import current_release_only
from tests.entries import make_entry, point

pytestmark = pytest.mark.no_pacing

SETPOINT = "number.s7_200_smart_setpoint"


@pytest.fixture
def platforms() -> list[Platform]:
    """Only the number platform."""
    return [Platform.NUMBER]


@current_release_only
async def test_snapshot(
    hass: HomeAssistant,
    setup_integration: MockConfigEntry,
    entity_registry: er.EntityRegistry,
    snapshot: SnapshotAssertion,
) -> None:
    await snapshot_platform(hass, entity_registry, snapshot, setup_integration.entry_id)


async def test_set_value_inverts_scaling(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, setup_integration: MockConfigEntry
) -> None:
    await hass.services.async_call(
        NUMBER_DOMAIN, SERVICE_SET_VALUE, {ATTR_ENTITY_ID: SETPOINT, ATTR_VALUE: 35}, blocking=True
    )
    assert s7_smart_ha_sim.get("VW20") == 50  # (35 - 10) / 0.5
    assert hass.states.get(SETPOINT).state == "35"


async def test_out_of_range_refused_before_sending(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, setup_integration: MockConfigEntry
) -> None:
    calls = dict(s7_smart_ha_sim.calls)
    with pytest.raises(ServiceValidationError):
        await hass.services.async_call(
            NUMBER_DOMAIN,
            SERVICE_SET_VALUE,
            {ATTR_ENTITY_ID: SETPOINT, ATTR_VALUE: 70},
            blocking=True,
        )
    assert dict(s7_smart_ha_sim.calls) == calls
    assert s7_smart_ha_sim.get("VW20") == 40


async def test_value_beyond_the_type_refused_before_sending(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """Without a range from the user, the point's own type still bounds what is sent."""
    entry = make_entry(
        hass, s7_smart_ha_sim, [point("level", "Level", "number", "VB60", "unsigned")]
    )
    assert await hass.config_entries.async_setup(entry.entry_id)
    state = hass.states.get("number.s7_200_smart_level")
    assert (state.attributes["min"], state.attributes["step"]) == (-2147483648.0, 1.0)
    calls = dict(s7_smart_ha_sim.calls)
    with pytest.raises(ServiceValidationError) as err:
        await hass.services.async_call(
            NUMBER_DOMAIN,
            SERVICE_SET_VALUE,
            {ATTR_ENTITY_ID: "number.s7_200_smart_level", ATTR_VALUE: 300},
            blocking=True,
        )
    assert str(err.value) == "Nothing was sent: VB60 300 is outside 0..255"
    assert dict(s7_smart_ha_sim.calls) == calls


async def test_float_point(hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator) -> None:
    entry = make_entry(hass, s7_smart_ha_sim, [point("flow", "Flow", "number", "VD100", "float")])
    assert await hass.config_entries.async_setup(entry.entry_id)
    state = hass.states.get("number.s7_200_smart_flow")
    assert (state.state, state.attributes["step"]) == ("21.5", 0.001)
    await hass.services.async_call(
        NUMBER_DOMAIN,
        SERVICE_SET_VALUE,
        {ATTR_ENTITY_ID: "number.s7_200_smart_flow", ATTR_VALUE: 2.25},
        blocking=True,
    )
    assert s7_smart_ha_sim.get("VD100", "float") == 2.25


async def test_quick_writes_show_at_once(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, setup_integration: MockConfigEntry
) -> None:
    """The refresh after a write is held back after another one; the PLC's ack shows anyway."""
    for value in (35, 36, 37):
        await hass.services.async_call(
            NUMBER_DOMAIN,
            SERVICE_SET_VALUE,
            {ATTR_ENTITY_ID: SETPOINT, ATTR_VALUE: value},
            blocking=True,
        )
        assert hass.states.get(SETPOINT).state == str(value)
    assert s7_smart_ha_sim.get("VW20") == 54  # (37 - 10) / 0.5
    assert s7_smart_ha_sim.calls["write"] == 3
