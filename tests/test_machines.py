"""Tests of the richer single-address entities on the S7-200 SMART simulator.

Value maps (select, enum sensor), a linear range, on/off codes and invert, alarm words.
"""

from __future__ import annotations

from unittest.mock import patch

from homeassistant.components.number import DOMAIN as NUMBER_DOMAIN, SERVICE_SET_VALUE
from homeassistant.components.select import DOMAIN as SELECT_DOMAIN, SERVICE_SELECT_OPTION
from homeassistant.components.switch import DOMAIN as SWITCH_DOMAIN
from homeassistant.const import (
    ATTR_ENTITY_ID,
    ATTR_OPTION,
    SERVICE_TURN_ON,
    STATE_OFF,
    STATE_ON,
    STATE_UNAVAILABLE,
    STATE_UNKNOWN,
    Platform,
)
from homeassistant.core import Event, EventStateChangedData, HomeAssistant, callback
from homeassistant.exceptions import ServiceValidationError
from homeassistant.helpers import entity_registry as er
from homeassistant.helpers.event import async_track_state_change_event
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, snapshot_platform
from syrupy.assertion import SnapshotAssertion

from simulators.s7_smart import S7SmartSimulator
from tests.conftest import current_release_only
from tests.entries import edit_point, make_entry, point, remove_point

pytestmark = pytest.mark.no_pacing

MAP = "0=Off;1=Auto;2=Manual"
POINTS = [
    point("mode", "Mode", "select", "VW30", "signed", value_map=MAP),
    point("state", "State", "sensor", "VW32", "signed", value_map=MAP, read_only=True),
    point(
        "valve",
        "Valve",
        "number",
        "VW40",
        "signed",
        raw_min=0,
        raw_max=27648,
        shown_min=0,
        shown_max=100,
        precision=1,
    ),
    point("heater", "Heater", "switch", "VW50", "signed", on_value=5, off_value=2),
    point("contact", "Contact", "binary_sensor", "I0.0", "signed", invert=True),
    point("alarms", "Alarms", "event", "VW70", "signed", bits="0=Overheat;3=Low water"),
    point("step", "Step", "button", "Q0.2", "signed", pulse=2.0),
]


@pytest.fixture
async def machines(hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator) -> MockConfigEntry:
    """The simulator's entry with a point of each richer kind, set up."""
    s7_smart_ha_sim.set("VW30", 1)
    s7_smart_ha_sim.set("VW32", 2)
    s7_smart_ha_sim.set("VW40", 13824)
    s7_smart_ha_sim.set("VW50", 2)
    entry = make_entry(hass, s7_smart_ha_sim, POINTS)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    return entry


@current_release_only
@pytest.mark.parametrize("platform", [Platform.SELECT, Platform.BUTTON, Platform.EVENT])
async def test_snapshot(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    entity_registry: er.EntityRegistry,
    snapshot: SnapshotAssertion,
    platform: Platform,
) -> None:
    """The entities of the new platforms, one platform at a time."""
    entry = make_entry(hass, s7_smart_ha_sim, POINTS)
    with patch("custom_components.plc_bridge.PLATFORMS", [platform]):
        assert await hass.config_entries.async_setup(entry.entry_id)
        await hass.async_block_till_done()
    await snapshot_platform(hass, entity_registry, snapshot, entry.entry_id)


async def refresh(entry: MockConfigEntry, times: int = 1) -> None:
    """Poll the PLC now (`times` times), as the poll interval would."""
    for _ in range(times):
        await entry.runtime_data.coordinator.async_refresh()


async def test_states_shown(hass: HomeAssistant, machines: MockConfigEntry) -> None:
    mode = hass.states.get("select.s7_200_smart_mode")
    assert mode.state == "Auto"
    assert mode.attributes["options"] == ["Off", "Auto", "Manual"]
    state = hass.states.get("sensor.s7_200_smart_state")
    assert state.state == "Manual"
    assert state.attributes["device_class"] == "enum"
    assert state.attributes["options"] == ["Off", "Auto", "Manual"]
    valve = hass.states.get("number.s7_200_smart_valve")
    assert (valve.state, valve.attributes["min"], valve.attributes["max"]) == ("50.0", 0, 100)
    assert valve.attributes["step"] == 0.1
    assert hass.states.get("switch.s7_200_smart_heater").state == STATE_OFF
    assert hass.states.get("binary_sensor.s7_200_smart_contact").state == STATE_OFF  # NC, I0.0 on
    overheat = hass.states.get("binary_sensor.s7_200_smart_overheat")
    assert (overheat.state, overheat.attributes["device_class"]) == (STATE_OFF, "problem")
    assert hass.states.get("event.s7_200_smart_alarms").state == STATE_UNKNOWN


async def test_select_writes_the_code(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, machines: MockConfigEntry
) -> None:
    await hass.services.async_call(
        SELECT_DOMAIN,
        SERVICE_SELECT_OPTION,
        {ATTR_ENTITY_ID: "select.s7_200_smart_mode", ATTR_OPTION: "Manual"},
        blocking=True,
    )
    assert s7_smart_ha_sim.get("VW30") == 2
    assert hass.states.get("select.s7_200_smart_mode").state == "Manual"


async def test_unmapped_value_logged_once(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    machines: MockConfigEntry,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """Unknown outside the map, logged once; again after the value was in the map and left."""
    s7_smart_ha_sim.set("VW32", 7)
    await refresh(machines, 3)
    assert hass.states.get("sensor.s7_200_smart_state").state == STATE_UNKNOWN
    logged = [r for r in caplog.records if "value map does not name" in r.getMessage()]
    assert [r.getMessage() for r in logged] == [
        "State: the PLC holds 7, which its value map does not name; shown as unknown"
    ]
    s7_smart_ha_sim.set("VW32", 0)
    await refresh(machines)
    assert hass.states.get("sensor.s7_200_smart_state").state == "Off"
    s7_smart_ha_sim.set("VW32", 9)
    await refresh(machines, 2)
    logged = [r for r in caplog.records if "value map does not name" in r.getMessage()]
    assert len(logged) == 2


async def test_linear_range_written_back(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    machines: MockConfigEntry,
) -> None:
    """25 % is written as 6912; above the raw range the value shows clamped; 150 % is refused."""
    await hass.services.async_call(
        NUMBER_DOMAIN,
        SERVICE_SET_VALUE,
        {ATTR_ENTITY_ID: "number.s7_200_smart_valve", "value": 25},
        blocking=True,
    )
    assert s7_smart_ha_sim.get("VW40") == 6912
    writes = s7_smart_ha_sim.calls["write"]
    with pytest.raises(ServiceValidationError):
        await hass.services.async_call(
            NUMBER_DOMAIN,
            SERVICE_SET_VALUE,
            {ATTR_ENTITY_ID: "number.s7_200_smart_valve", "value": 150},
            blocking=True,
        )
    assert s7_smart_ha_sim.calls["write"] == writes
    s7_smart_ha_sim.set("VW40", 30000)
    await refresh(machines)
    assert hass.states.get("number.s7_200_smart_valve").state == "100.0"


async def test_switch_codes(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    machines: MockConfigEntry,
) -> None:
    """On is written as 5; a value that is neither code shows as unknown."""
    await hass.services.async_call(
        SWITCH_DOMAIN,
        SERVICE_TURN_ON,
        {ATTR_ENTITY_ID: "switch.s7_200_smart_heater"},
        blocking=True,
    )
    assert s7_smart_ha_sim.get("VW50") == 5
    assert hass.states.get("switch.s7_200_smart_heater").state == STATE_ON
    s7_smart_ha_sim.set("VW50", 7)
    await refresh(machines)
    assert hass.states.get("switch.s7_200_smart_heater").state == STATE_UNKNOWN


async def test_alarm_word(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    machines: MockConfigEntry,
) -> None:
    """Each named bit is a binary sensor; the event entity fires `<name> raised` and `cleared`."""
    fired: list[tuple[str, str]] = []

    @callback
    def seen(event: Event[EventStateChangedData]) -> None:
        state = event.data["new_state"]
        if state is not None and "event_type" in state.attributes:
            fired.append((state.attributes["event_type"], state.attributes["name"]))

    async_track_state_change_event(hass, "event.s7_200_smart_alarms", seen)
    reads = s7_smart_ha_sim.calls["read"]
    s7_smart_ha_sim.set("VW70", 0b0001)
    await refresh(machines)
    assert hass.states.get("binary_sensor.s7_200_smart_overheat").state == STATE_ON
    s7_smart_ha_sim.set("VW70", 0b1110)  # bits 1 and 2 have no name
    await refresh(machines)
    assert hass.states.get("binary_sensor.s7_200_smart_overheat").state == STATE_OFF
    assert hass.states.get("binary_sensor.s7_200_smart_low_water").state == STATE_ON
    await hass.async_block_till_done()  # 2026.2 hands state changes to trackers a loop later
    assert fired == [
        ("Overheat raised", "Overheat"),
        ("Overheat cleared", "Overheat"),
        ("Low water raised", "Low water"),
    ]
    assert s7_smart_ha_sim.calls["read"] - reads == 2  # one read per poll for every kind


async def test_edited_bits(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    machines: MockConfigEntry,
    entity_registry: er.EntityRegistry,
) -> None:
    """A bit taken out of the word goes from the registry; the others keep their entities."""
    overheat = entity_registry.async_get("binary_sensor.s7_200_smart_overheat")
    edit_point(hass, machines, "alarms", bits="0=Overheat;5=Pump fault")
    await hass.async_block_till_done()
    assert entity_registry.async_get("binary_sensor.s7_200_smart_low_water") is None
    assert entity_registry.async_get("binary_sensor.s7_200_smart_overheat").id == overheat.id
    assert hass.states.get("binary_sensor.s7_200_smart_pump_fault").state == STATE_OFF
    remove_point(hass, machines, "alarms")
    await hass.async_block_till_done()
    assert entity_registry.async_get("binary_sensor.s7_200_smart_overheat") is None
    assert entity_registry.async_get("event.s7_200_smart_alarms") is None


async def test_refused_and_failing_alone(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """A read-only select is never written; an alarm word at a bad address fails alone."""
    s7_smart_ha_sim.set("VW30", 1)
    entry = make_entry(
        hass,
        s7_smart_ha_sim,
        [
            point("mode", "Mode", "select", "VW30", "signed", value_map=MAP, read_only=True),
            point("alarms", "Alarms", "event", "VX1", "signed", bits="0=Overheat"),
        ],
    )
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    with pytest.raises(ServiceValidationError) as err:
        await hass.services.async_call(
            SELECT_DOMAIN,
            SERVICE_SELECT_OPTION,
            {ATTR_ENTITY_ID: "select.s7_200_smart_mode", ATTR_OPTION: "Off"},
            blocking=True,
        )
    assert err.value.translation_key == "read_only"
    assert s7_smart_ha_sim.calls["write"] == 0
    assert hass.states.get("select.s7_200_smart_mode").state == "Auto"
    assert hass.states.get("event.s7_200_smart_alarms").state == STATE_UNAVAILABLE
    assert hass.states.get("binary_sensor.s7_200_smart_overheat").state == STATE_UNAVAILABLE
