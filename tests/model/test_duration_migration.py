"""Entries of version 2.1: TecoApi and PLCnext times keep their entities and what they show."""

from __future__ import annotations

from typing import Any

from homeassistant.const import ATTR_DEVICE_CLASS, ATTR_UNIT_OF_MEASUREMENT
from homeassistant.core import HomeAssistant
from homeassistant.helpers import entity_registry as er, issue_registry as ir
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import DOMAIN
from custom_components.plc_bridge.model.migration import kept_duration
from simulators.plcnext import PlcnextSimulator
from simulators.s7_smart import S7SmartSimulator
from simulators.tecomat import TecomatSimulator
from tests.entries import DEVICE_ID, POINTS, PointData, device, point, set_up, sim_data
from tests.harness import (
    PLCNEXT_ENTRY_ID,
    TECOMAT_ENTRY_ID,
    TECOMAT_SERIAL,
    plcnext_data,
    tecomat_data,
)

pytestmark = pytest.mark.no_pacing

MAIN = "Arp.Plc.Eclr/MainInstance."


def old_entry(
    hass: HomeAssistant,
    entry_id: str,
    unique_id: str,
    data: dict[str, Any],
    points: list[PointData],
) -> MockConfigEntry:
    """Add an entry as version 2.1 stored it, its entities registered under old entity ids."""
    entry = MockConfigEntry(
        domain=DOMAIN,
        title="Old PLC",
        entry_id=entry_id,
        unique_id=unique_id,
        data=data,
        subentries_data=[device(points, title="Old PLC")],
        version=2,
        minor_version=1,
    )
    entry.add_to_hass(hass)
    registry = er.async_get(hass)
    for point_id, point_data in points:
        registry.async_get_or_create(
            point_data["platform"],
            DOMAIN,
            f"{unique_id if entry_id == TECOMAT_ENTRY_ID else entry_id}_{point_id}",
            config_entry=entry,
            config_subentry_id=DEVICE_ID,
            suggested_object_id=f"old_{point_id}",
        )
    return entry


async def test_tecomat_times_keep_their_text(
    hass: HomeAssistant, tecomat_ha_sim: TecomatSimulator
) -> None:
    """A TIME sensor and a TOD text entity show hh:mm:ss.zzz as before, under the same ids."""
    points = [
        point("time", "Time", "sensor", "plcData.varTime", "TIME"),
        point("tod", "Tod", "text", "plcData.varTod", "TOD"),
    ]
    entry = old_entry(hass, TECOMAT_ENTRY_ID, TECOMAT_SERIAL, tecomat_data(tecomat_ha_sim), points)
    await set_up(hass, entry)
    assert (entry.version, entry.minor_version) == (2, 2)
    stored = entry.subentries[DEVICE_ID].data["points"]
    assert stored["time"]["as_text"] is True
    registry = er.async_get(hass)
    assert registry.async_get("sensor.old_time").unique_id == f"{TECOMAT_SERIAL}_time"
    time = hass.states.get("sensor.old_time")
    assert time.state == "120:02:03.450"
    assert ATTR_DEVICE_CLASS not in time.attributes
    assert hass.states.get("text.old_tod").state == "07:30:00.000"
    assert registry.async_get_entity_id("text", DOMAIN, f"{TECOMAT_SERIAL}_tod") == "text.old_tod"
    assert told_of_seconds(hass, entry)


def told_of_seconds(hass: HomeAssistant, entry: MockConfigEntry) -> bool:
    """True when the entry's issue says the actions now take seconds (kept across restarts)."""
    issue = ir.async_get(hass).async_get_issue(DOMAIN, f"times_in_seconds_{entry.entry_id}")
    return issue is not None and issue.is_persistent


async def test_other_families_are_not_told(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """An S7-200 SMART entry of 2.1 is migrated too, with nothing to tell about times."""
    entry = MockConfigEntry(
        domain=DOMAIN,
        title="Old PLC",
        data=sim_data(s7_smart_ha_sim),
        subentries_data=[device(POINTS, title="Old PLC")],
        version=2,
        minor_version=1,
    )
    entry.add_to_hass(hass)
    await set_up(hass, entry)
    assert entry.minor_version == 2
    assert not told_of_seconds(hass, entry)


async def test_plcnext_times_keep_their_counts(
    hass: HomeAssistant, plcnext_ha_sim: PlcnextSimulator
) -> None:
    """Counts in a time unit become durations in it; other counts stay integers."""
    points = [
        point(
            "runtime",
            "Runtime",
            "sensor",
            MAIN + "Runtime",
            "TIME",
            unit_of_measurement="ms",
            state_class="total_increasing",
        ),
        point("setting", "Setting", "number", MAIN + "Runtime", "TIME", min=0.0, max=100_000.0),
        point("uptime", "Uptime", "sensor", MAIN + "Uptime", "LTIME", read_only=True),
        point("shifted", "Shifted", "sensor", MAIN + "Runtime", "TIME", offset=5.0),
    ]
    entry = old_entry(hass, PLCNEXT_ENTRY_ID, "plcnext:1", plcnext_data(plcnext_ha_sim), points)
    await set_up(hass, entry)
    assert entry.minor_version == 2
    stored = entry.subentries[DEVICE_ID].data["points"]
    assert [stored[key]["data_type"] for key in ("runtime", "setting", "uptime", "shifted")] == [
        "TIME",
        "TIME",
        "LINT",  # nanoseconds: no unit of Home Assistant's counts them
        "DINT",  # an offset: no duration
    ]
    registry = er.async_get(hass)
    assert registry.async_get("sensor.old_runtime").unique_id == f"{PLCNEXT_ENTRY_ID}_runtime"
    runtime = hass.states.get("sensor.old_runtime")
    assert runtime.state == "90000"
    assert runtime.attributes[ATTR_DEVICE_CLASS] == "duration"
    assert runtime.attributes[ATTR_UNIT_OF_MEASUREMENT] == "ms"
    assert runtime.attributes["state_class"] == "total_increasing"
    setting = hass.states.get("number.old_setting")
    assert (setting.state, setting.attributes[ATTR_UNIT_OF_MEASUREMENT]) == ("90000", "ms")
    assert setting.attributes["max"] == 100_000
    assert hass.states.get("sensor.old_uptime").state == "5000000000"
    assert hass.states.get("sensor.old_shifted").state == "90005"
    assert told_of_seconds(hass, entry)


def test_kept_duration() -> None:
    """What decides each case: the vendor, the platform, the scale and the unit."""
    _, data = point("x", "X", "sensor", "a.b", "TIME")
    assert kept_duration("s7", data) == data
    assert kept_duration("tecomat", data)["as_text"] is True
    seconds = kept_duration("plcnext", data | {"scale": 0.001, "unit_of_measurement": "s"})
    assert (seconds["unit_of_measurement"], seconds["scale"]) == ("s", 1.0)
    micros = kept_duration("plcnext", data | {"data_type": "LTIME", "scale": 0.001})
    assert micros["unit_of_measurement"] == "μs"
    assert kept_duration("plcnext", data | {"unit_of_measurement": "s"})["data_type"] == "DINT"
    assert kept_duration("plcnext", data | {"state_class": "measurement"})["data_type"] == "DINT"
    assert kept_duration("plcnext", data | {"value_map": "0=Off"})["data_type"] == "DINT"
    _, switch = point("x", "X", "switch", "a.b", "TIME")
    assert kept_duration("plcnext", switch)["data_type"] == "DINT"
