"""Tests of the sensors: point values, scaling, and the PLC's status as diagnostic sensors."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from datetime import datetime, timedelta
from unittest.mock import patch
from zoneinfo import ZoneInfo

from freezegun.api import FrozenDateTimeFactory
from homeassistant.const import STATE_UNAVAILABLE, STATE_UNKNOWN, Platform
from homeassistant.core import HomeAssistant
from homeassistant.helpers import device_registry as dr, entity_registry as er
from homeassistant.util import dt as dt_util
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, snapshot_platform
from syrupy.assertion import SnapshotAssertion

from custom_components.plc_bridge.const import DOMAIN
from custom_components.plc_bridge.entity import PlcPointDescription
from custom_components.plc_bridge.model.conversion import scaled
from custom_components.plc_bridge.plc import Point, ReadResult, ValueKind
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from simulators.s7_smart import S7SmartSimulator
from tests.conftest import current_release_only
from tests.entries import DEVICE_ID, make_entry, point, poll

pytestmark = pytest.mark.no_pacing

DRIFT = "sensor.s7_200_smart_clock_drift"


@pytest.fixture
def platforms() -> list[Platform]:
    """Only the sensor platform."""
    return [Platform.SENSOR]


@current_release_only
@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_snapshot(
    hass: HomeAssistant,
    setup_integration: MockConfigEntry,
    entity_registry: er.EntityRegistry,
    snapshot: SnapshotAssertion,
) -> None:
    # The drift and the last poll depend on when the test runs (checked by their own tests).
    entity_registry.async_remove(DRIFT)
    entity_registry.async_remove("sensor.s7_200_smart_last_successful_poll")
    await snapshot_platform(hass, entity_registry, snapshot, setup_integration.entry_id)


async def test_clock_drift_is_quiet(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    setup_integration: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """The drift is whole seconds; a clock keeping time writes no state, a jump of 2 s does."""
    zone = ZoneInfo(hass.config.time_zone)
    freezer.move_to(dt_util.now().replace(microsecond=0))  # PLC clocks tick in whole seconds

    def plc_time(ahead: float) -> datetime:
        """The PLC's local clock, `ahead` seconds ahead of Home Assistant's, whole seconds."""
        moment = dt_util.now().astimezone(zone) + timedelta(seconds=ahead)
        return moment.replace(tzinfo=None, microsecond=0)

    s7_smart_ha_sim.clock = plc_time(10 + 20.4)  # the poll below moves time by 10 s
    await poll(hass, freezer)
    state = hass.states.get(DRIFT)
    assert state.state == "20"
    assert state.attributes["unit_of_measurement"] == "s"
    registered = er.async_get(hass).async_get(DRIFT)
    assert registered.options["sensor"]["suggested_display_precision"] == 0  # "20 s", not "20.00"
    for ahead in (20.9, 19.6, 21.0):  # a clock keeping time, read at whatever fraction
        s7_smart_ha_sim.clock = plc_time(10 + ahead)
        await poll(hass, freezer)
        assert hass.states.get(DRIFT).last_updated == state.last_updated
    s7_smart_ha_sim.clock = plc_time(10 + 25)
    await poll(hass, freezer)
    assert hass.states.get(DRIFT).state == "25"


async def test_status_fields_disabled_by_default(
    hass: HomeAssistant, setup_integration: MockConfigEntry, entity_registry: er.EntityRegistry
) -> None:
    entry = entity_registry.async_get("sensor.s7_200_smart_system_status")
    assert entry is not None
    assert entry.disabled_by is er.RegistryEntryDisabler.INTEGRATION
    assert hass.states.get("sensor.s7_200_smart_operating_mode").state == "run"


async def test_values_follow_the_plc(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    setup_integration: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    s7_smart_ha_sim.set("VW10", -12)
    s7_smart_ha_sim.mode = "STOP"
    await poll(hass, freezer)
    assert hass.states.get("sensor.s7_200_smart_pressure").state == "-1.2"
    assert hass.states.get("sensor.s7_200_smart_operating_mode").state == "stop"

    s7_smart_ha_sim.mode = "SOMETHING ELSE"
    await poll(hass, freezer)
    assert hass.states.get("sensor.s7_200_smart_operating_mode").state == STATE_UNKNOWN


@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_vendor_status_fields(hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator) -> None:
    """Status fields beyond the usual three become sensors, translated where the name is known."""
    read = S7SmartClient._read

    async def with_extra(
        client: S7SmartClient, points: Sequence[Point], *, poll: bool = True
    ) -> ReadResult:
        # The S7-200 SMART reports no such fields: a vendor that does is imitated here.
        result = await read(client, points, poll=poll)
        extra = {"cycle_time": "12 ms", "Backplane": "ok"}
        return replace(result, status=replace(result.status, extra=extra))

    entry = make_entry(hass, s7_smart_ha_sim, [])
    with patch.object(S7SmartClient, "_read", with_extra):
        assert await hass.config_entries.async_setup(entry.entry_id)
        await hass.async_block_till_done()
    assert hass.states.get("sensor.s7_200_smart_cycle_time").state == "12 ms"
    assert hass.states.get("sensor.s7_200_smart_backplane").state == "ok"


@pytest.mark.parametrize(
    ("raw", "scale", "offset", "expected"),
    [
        (23, 0.1, 0.0, 2.3),
        (40, 0.5, 10.0, 30),
        (7, 2.0, 1.0, 15),
        (1.5, 1.0, 0.0, 1.5),
        (3, 1.0, 0.0, 3),
    ],
)
def test_scaling(raw: float, scale: float, offset: float, expected: float) -> None:
    value = scaled(raw, scale, offset)
    assert value == expected
    assert type(value) is type(expected)


@pytest.mark.parametrize(
    ("kind", "value", "raw"),
    [(ValueKind.INTEGER, 30.0, 40), (ValueKind.FLOAT, 11.25, 2.5), (ValueKind.INTEGER, 10.3, 1)],
)
def test_inverse_scaling(kind: ValueKind, value: float, raw: float) -> None:
    description = PlcPointDescription(
        key="x", point=Point("VW0", "signed"), kind=kind, scale=0.5, offset=10.0
    )
    assert description.raw_fn(value) == raw


async def test_entities_belong_to_their_subentry(
    hass: HomeAssistant,
    setup_integration: MockConfigEntry,
    entity_registry: er.EntityRegistry,
    device_registry: dr.DeviceRegistry,
) -> None:
    """Points belong to their device subentry's device, hanging off the PLC's own device."""
    point_entry = entity_registry.async_get("sensor.s7_200_smart_temperature")
    status_entry = entity_registry.async_get("sensor.s7_200_smart_operating_mode")
    assert point_entry is not None
    assert status_entry is not None
    assert point_entry.config_subentry_id == DEVICE_ID
    assert status_entry.config_subentry_id is None
    assert point_entry.device_id is not None
    assert status_entry.device_id is not None
    point_device = device_registry.async_get(point_entry.device_id)
    plc_device = device_registry.async_get(status_entry.device_id)
    assert point_device is not None
    assert plc_device is not None
    assert point_device.via_device_id == plc_device.id
    assert point_device.identifiers == {(DOMAIN, DEVICE_ID)}
    assert plc_device.model == "S7-200 SMART"


async def test_other_kinds_of_points(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """The clock as a timestamp, a bit as 0/1, and an address the vendor cannot parse."""
    entry = make_entry(
        hass,
        s7_smart_ha_sim,
        [
            point("clock", "Clock", "sensor", "DATE", "signed"),
            point("bit", "Bit", "sensor", "I0.0", "signed"),
            point("bad", "Bad", "sensor", "VX1", "signed"),
        ],
    )
    assert await hass.config_entries.async_setup(entry.entry_id)
    clock = hass.states.get("sensor.s7_200_smart_clock")
    assert clock.state == "2026-03-01T20:30:00+00:00"
    assert clock.attributes["device_class"] == "timestamp"
    assert hass.states.get("sensor.s7_200_smart_bit").state == "1"
    assert hass.states.get("sensor.s7_200_smart_bad").state == STATE_UNAVAILABLE
