"""Every platform's entities, as snapshots: one machine holding every kind, on one simulator.

The S7-200 SMART simulator holds a machine with a point or an entity of several points of each
kind; each platform is set up alone and its states and entity registry entries are compared
with tests/snapshots/test_snapshots.ambr. Time stands at the simulator's clock, so the link's
own entities (last poll, clock drift) hold no time of the run; ids and ports are left out.
Update with `--snapshot-update` on the current Home Assistant.
"""

from __future__ import annotations

from collections.abc import AsyncGenerator
from unittest.mock import patch

from homeassistant.const import Platform
from homeassistant.core import HomeAssistant
from homeassistant.helpers import entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, snapshot_platform
from syrupy.assertion import SnapshotAssertion

from custom_components.plc_bridge.model.kinds import PLATFORMS
from simulators.s7_smart import S7SmartSimulator
from tests.conftest import current_release_only
from tests.entries import ENTRY_ID, UNIQUE_ID, add_entry, device, point, sim_data, unload_all
from tests.test_climate import BOILER

pytestmark = [
    pytest.mark.no_pacing,
    pytest.mark.freeze_time("2026-03-01 20:30:00+00:00"),  # the simulator's clock: no drift
    current_release_only,
]

RANGE = {"raw_min": 0, "raw_max": 27648, "shown_min": 0, "shown_max": 100}
STATES = "0=Off;1=Auto;2=Manual"

EVERY_KIND = [
    point(
        "temperature",
        "Temperature",
        "sensor",
        "VD100",
        "float",
        unit_of_measurement="°C",
        device_class="temperature",
        state_class="measurement",
    ),
    point("state", "State", "sensor", "VW32", "signed", value_map=STATES, read_only=True),
    point("door", "Door", "binary_sensor", "I0.0", "signed", device_class="door"),
    point("pump", "Pump", "switch", "Q0.0", "signed"),
    point("feed_state", "Feed", "switch", "I0.3", "signed", role="state", read_only=True),
    point("feed_command", "Feed", "switch", "M1.0", "signed", role="command"),
    point(
        "setpoint",
        "Setpoint",
        "number",
        "VW20",
        "signed",
        scale=0.5,
        offset=10.0,
        min=10.0,
        max=60.0,
        step=0.5,
    ),
    point("clock", "Clock", "datetime", "DATE", "signed"),
    point("label", "Label", "text", "VB200", "string"),
    point("mode", "Mode", "select", "VW30", "signed", value_map=STATES),
    point("step", "Step", "button", "Q0.2", "signed", pulse=2.0),
    point("alarms", "Alarms", "event", "VW70", "signed", bits="0=Overheat;3=Low water"),
    point("s1", "Shutter", "cover", "VW40", "signed", role="position", read_only=True, **RANGE),
    point("s2", "Shutter", "cover", "VW42", "signed", role="set_position", **RANGE),
    point("s3", "Shutter", "cover", "Q0.4", "signed", role="open"),
    point("s4", "Shutter", "cover", "Q0.5", "signed", role="close"),
    point("s5", "Shutter", "cover", "Q0.6", "signed", role="stop", pulse=1.0),
    point("s6", "Shutter", "cover", "I0.1", "signed", role="open_limit", read_only=True),
    point("s7", "Shutter", "cover", "I0.2", "signed", role="closed_limit", read_only=True),
    *BOILER,
    point("v1", "Mixer", "valve", "VW80", "signed", role="position", read_only=True, **RANGE),
    point("v2", "Mixer", "valve", "VW82", "signed", role="set_position", **RANGE),
    point("w1", "Inlet", "valve", "Q1.0", "signed", role="open"),
    point("w2", "Inlet", "valve", "Q1.1", "signed", role="close"),
    point("w3", "Inlet", "valve", "I1.0", "signed", role="closed_limit", read_only=True),
    point("f1", "Vent", "fan", "I1.1", "signed", role="state", read_only=True),
    point("f2", "Vent", "fan", "M3.0", "signed", role="command"),
    point("f3", "Vent", "fan", "VW84", "signed", role="percentage"),
    point("f4", "Vent", "fan", "VW86", "signed", role="preset", value_map="0=Low;1=High"),
    point("l1", "Lamp", "light", "I0.5", "signed", role="state", read_only=True),
    point("l2", "Lamp", "light", "M2.0", "signed", role="command", pulse=0.5),
    point("l3", "Lamp", "light", "VW60", "signed", role="brightness", **RANGE),
    point(
        "h1",
        "Tank",
        "water_heater",
        "VW90",
        "signed",
        role="current_temperature",
        scale=0.1,
        read_only=True,
    ),
    point(
        "h2",
        "Tank",
        "water_heater",
        "VW92",
        "signed",
        role="target_temperature",
        scale=0.1,
        min=30.0,
        max=70.0,
        step=1.0,
    ),
    point(
        "h3",
        "Tank",
        "water_heater",
        "VW94",
        "signed",
        role="operation_mode",
        value_map="0=off;1=eco;2=performance",
    ),
]
"""A machine with every kind: single points of each point platform, and every composite."""

VALUES = {
    "VW32": 2,
    "VW30": 1,
    "VW40": 13824,
    "VW50": 215,
    "VW52": 200,
    "VW54": 1,
    "VW56": 1,
    "VW80": 6912,
    "I1.0": True,
    "VW84": 30,
    "VW86": 1,
    "I0.5": True,
    "VW60": 13824,
    "VW90": 452,
    "VW92": 550,
    "VW94": 1,
}
"""What the simulator holds beside the harness's values of POINTS (VD100, VW20, VB200...)."""


@pytest.fixture
async def plant(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, platform: Platform
) -> AsyncGenerator[MockConfigEntry]:
    """The simulator's entry with the machine of every kind, set up with one platform."""
    for address, value in VALUES.items():
        s7_smart_ha_sim.set(address, value)
    entry = add_entry(
        hass,
        title="S7-200 SMART",
        entry_id=ENTRY_ID,
        unique_id=UNIQUE_ID,
        data=sim_data(s7_smart_ha_sim),
        subentries=[device(EVERY_KIND, title="Plant")],
    )
    with patch("custom_components.plc_bridge.PLATFORMS", [platform]):
        assert await hass.config_entries.async_setup(entry.entry_id)
        await hass.async_block_till_done()
        yield entry
        await unload_all(hass)


def test_every_platform_has_an_entity_kind() -> None:
    """The machine holds something of every platform the integration sets up."""
    kinds = {data["platform"] for _, data in EVERY_KIND}
    assert kinds == {platform.value for platform in PLATFORMS}


@pytest.mark.parametrize("platform", PLATFORMS, ids=str)
@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_snapshot(
    hass: HomeAssistant,
    plant: MockConfigEntry,
    entity_registry: er.EntityRegistry,
    snapshot: SnapshotAssertion,
) -> None:
    """The platform's entities, their registry entries and states, as the snapshot holds."""
    await snapshot_platform(hass, entity_registry, snapshot, plant.entry_id)
