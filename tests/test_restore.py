"""Restored values: after a restart every entity shows its last value until a poll reads it.

Home Assistant is restarted in the harness as core's restore tests do it: the entry is unloaded
(its values go to its file, in the harness's storage), Home Assistant's restore store is dumped
and loaded back (`async_mock_restore_state_shutdown_restart`: the event restores from it), then
the entry is set up again. The S7-200 SMART is paced (one request a second, 32 nodes each):
the setup's first poll reads the first 32 points only, so the entities of every kind (placed
after them) are shown before their first poll, then polled by the poll that follows at once.
Its pacing is set on the class after the connect: under the frozen clock the requests go at
once, while the coordinator plans as for the paced PLC.
"""

from __future__ import annotations

import asyncio
from datetime import timedelta
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.const import (
    EVENT_HOMEASSISTANT_FINAL_WRITE,
    EVENT_STATE_CHANGED,
    STATE_UNAVAILABLE,
)
from homeassistant.core import Event, EventStateChangedData, HomeAssistant, State, callback
from homeassistant.helpers import entity_registry as er, restore_state
import pytest
from pytest_homeassistant_custom_component.common import (
    MockConfigEntry,
    async_fire_time_changed,
    async_mock_restore_state_shutdown_restart,
    mock_restore_cache_with_extra_data,
)

from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from custom_components.plc_bridge.runtime.restore import SAVE_DELAY, storage_key
from simulators.s7_smart import S7SmartSimulator
from tests.entries import PointData, edit_point, make_entry, point, poll, read_edits, set_up

pytestmark = pytest.mark.no_pacing

RANGE = {"raw_min": 0, "raw_max": 27648, "shown_min": 0, "shown_max": 100}
FIRST = [point(f"w{i}", f"Word {i}", "sensor", f"VW{1000 + 2 * i}", "signed") for i in range(32)]
"""What the setup's paced first poll reads: the points of every kind come after these."""
KINDS: list[PointData] = [
    point("temp", "Temperature", "sensor", "VD100", "float", unit_of_measurement="°C"),
    point("door", "Door", "binary_sensor", "I0.0", "signed", device_class="door"),
    point("pump", "Pump", "switch", "Q0.0", "signed"),
    point("set", "Setpoint", "number", "VW20", "signed", min=0.0, max=100.0, step=1.0),
    point("kmode", "Mode", "select", "VW30", "signed", value_map="0=Off;1=Auto"),
    point("name", "Name", "text", "VB200", "string"),
    point("s1", "Shutter", "cover", "VW40", "signed", role="position", read_only=True, **RANGE),
    point("s2", "Shutter", "cover", "VW42", "signed", role="set_position", **RANGE),
    point("v1", "Mixer", "valve", "VW80", "signed", role="position", read_only=True, **RANGE),
    point("v2", "Mixer", "valve", "VW82", "signed", role="set_position", **RANGE),
    point("f1", "Vent", "fan", "I1.1", "signed", role="state", read_only=True),
    point("f2", "Vent", "fan", "M3.0", "signed", role="command"),
    point("f3", "Vent", "fan", "VW84", "signed", role="percentage"),
    point("l1", "Lamp", "light", "I1.3", "signed", role="state", read_only=True),
    point("l2", "Lamp", "light", "M2.0", "signed", role="command"),
    point("l3", "Lamp", "light", "VW60", "signed", role="brightness", **RANGE),
    point("c1", "Boiler", "climate", "VW50", "signed", role="current_temperature", scale=0.1),
    point("c2", "Boiler", "climate", "VW52", "signed", role="target_temperature", scale=0.1),
    point("c3", "Boiler", "climate", "VW54", "signed", role="hvac_mode", value_map="0=off;1=heat"),
    point("p1", "Heater", "switch", "I0.3", "signed", role="state", read_only=True),
    point("p2", "Heater", "switch", "M1.0", "signed", role="command"),
    point("alarms", "Alarms", "event", "VW70", "signed", bits="0=Overheat"),
]
BEFORE: dict[str, Any] = {
    "VD100": (21.5, "float"),
    "I0.0": (True, None),
    "Q0.0": (True, None),
    "VW20": (40, None),
    "VW30": (1, None),
    "VB200": ("Line 1", "string"),
    "VW40": (13824, None),
    "VW42": (13824, None),
    "VW80": (6912, None),
    "VW82": (6912, None),
    "I1.1": (True, None),
    "VW84": (60, None),
    "I1.3": (True, None),
    "VW60": (27648, None),
    "VW50": (215, None),
    "VW52": (220, None),
    "VW54": (1, None),
    "I0.3": (True, None),
    "VW70": (1, None),
}
"""What the PLC holds before the restart (address: value, simulator type)."""
AFTER: dict[str, Any] = {
    "VD100": (23.0, "float"),
    "I0.0": (False, None),
    "Q0.0": (False, None),
    "VW20": (55, None),
    "VW30": (0, None),
    "VB200": ("Line 2", "string"),
    "VW40": (0, None),
    "VW42": (0, None),
    "VW80": (27648, None),
    "VW82": (27648, None),
    "I1.1": (False, None),
    "VW84": (0, None),
    "I1.3": (False, None),
    "VW60": (0, None),
    "VW50": (190, None),
    "VW52": (200, None),
    "VW54": (0, None),
    "I0.3": (False, None),
    "VW70": (0, None),
}
"""What it holds while Home Assistant is down: every value differs."""


def hold(sim: S7SmartSimulator, values: dict[str, Any]) -> None:
    """Have the simulator hold these values."""
    for address, (value, kind) in values.items():
        if kind is None:
            sim.set(address, value)
        else:
            sim.set(address, value, kind)


def entity_ids(hass: HomeAssistant, entry: MockConfigEntry) -> dict[str, str]:
    """Return the entity id of each of the entry's entities of KINDS, by unique id suffix."""
    registry = er.async_get(hass)
    found = {
        registry_entry.unique_id.rsplit("_", 1)[-1]: registry_entry.entity_id
        for registry_entry in er.async_entries_for_config_entry(registry, entry.entry_id)
    }
    return {key: found[key] for key in ("temp", "door", "pump", "set", "kmode", "name")} | {
        name: entity_id
        for entity_id in found.values()
        for name in ("shutter", "mixer", "vent", "lamp", "boiler", "heater", "alarms", "overheat")
        if entity_id.endswith(f"_{name}")
    }


def paced_after_connect(monkeypatch: pytest.MonkeyPatch) -> None:
    """Pace the S7-200 SMART as the real one once it is connected (see the module's text)."""
    connect = S7SmartClient.connect

    async def connected(self: S7SmartClient) -> Any:
        """Connect, then plan reads at one request a second."""
        device = await connect(self)
        monkeypatch.setattr(S7SmartClient, "request_interval", 1.0)
        return device

    monkeypatch.setattr(S7SmartClient, "connect", connected)


async def restart(
    hass: HomeAssistant,
    entry: MockConfigEntry,
    monkeypatch: pytest.MonkeyPatch,
    freezer: FrozenDateTimeFactory,
) -> dict[str, list[State]]:
    """Restart Home Assistant's side of the entry; return the states each entity wrote, in turn."""
    assert await hass.config_entries.async_unload(entry.entry_id)
    await hass.async_block_till_done()
    await async_mock_restore_state_shutdown_restart(hass)
    monkeypatch.setattr(S7SmartClient, "request_interval", 0.0)
    paced_after_connect(monkeypatch)
    written: dict[str, list[State]] = {}

    @callback
    def note(event: Event[EventStateChangedData]) -> None:
        """Keep each state written after the restart."""
        if (state := event.data["new_state"]) is not None:
            written.setdefault(state.entity_id, []).append(state)

    unsubscribe = hass.bus.async_listen(EVENT_STATE_CHANGED, note)
    await set_up(hass, entry)
    for _ in range(3):  # the poll that reads the others starts once the entities are added
        freezer.tick(timedelta(seconds=1))
        async_fire_time_changed(hass)
        await hass.async_block_till_done(wait_background_tasks=True)
    unsubscribe()
    return written


async def test_every_kind_shows_its_last_value_until_polled(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """After a restart each kind first shows its last state, restored, then the polled one.

    Nothing restored is written: the PLC gets no write request at all.
    """
    hold(s7_smart_ha_sim, BEFORE)
    entry = await set_up(hass, make_entry(hass, s7_smart_ha_sim, [*FIRST, *KINDS]))
    ids = entity_ids(hass, entry)
    assert len(ids) == 14  # the six plain kinds, six of several points, an alarm word, its bit
    before = {key: hass.states.get(entity_id) for key, entity_id in ids.items()}
    assert all(state is not None and state.state != STATE_UNAVAILABLE for state in before.values())
    hold(s7_smart_ha_sim, AFTER)
    written = await restart(hass, entry, monkeypatch, freezer)
    for key, entity_id in ids.items():
        if key == "alarms":
            continue  # an event restores its last event itself (see the test below)
        old, states = before[key], written[entity_id]
        assert old is not None
        first, last = states[0], states[-1]
        assert first.state == old.state, key
        assert dict(first.attributes) == {**old.attributes, "restored": True}, key
        assert "restored" not in last.attributes, key
        assert last.state != STATE_UNAVAILABLE, key
        assert (last.state, dict(last.attributes)) != (old.state, dict(old.attributes)), key
    assert s7_smart_ha_sim.calls["write"] == 0
    await poll(hass, freezer)
    assert s7_smart_ha_sim.calls["write"] == 0
    assert entry.runtime_data.coordinator.stored.restored is None  # every point read: dropped


def kept(hass_storage: dict[str, Any], entry: MockConfigEntry) -> dict[str, Any]:
    """Return the values in the entry's file (what the harness's storage holds of it)."""
    return dict(hass_storage[storage_key(entry.entry_id)]["data"]["values"])


async def later(hass: HomeAssistant, freezer: FrozenDateTimeFactory, seconds: float) -> None:
    """Let `seconds` pass and wait for what they start."""
    freezer.tick(timedelta(seconds=seconds))
    async_fire_time_changed(hass)
    await hass.async_block_till_done(wait_background_tasks=True)


@pytest.fixture
async def kinds_entry(hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator) -> MockConfigEntry:
    """An entry of every kind, set up while the PLC holds BEFORE; then it holds AFTER."""
    hold(s7_smart_ha_sim, BEFORE)
    entry = await set_up(hass, make_entry(hass, s7_smart_ha_sim, KINDS))
    hold(s7_smart_ha_sim, AFTER)
    return entry


async def test_values_are_kept_when_home_assistant_stops(
    hass: HomeAssistant,
    hass_storage: dict[str, Any],
    kinds_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Home Assistant's last write at a stop writes the values of the last poll; nothing before."""
    await poll(hass, freezer)
    assert storage_key(kinds_entry.entry_id) not in hass_storage
    hass.bus.async_fire(EVENT_HOMEASSISTANT_FINAL_WRITE)
    await hass.async_block_till_done()
    values = kept(hass_storage, kinds_entry)
    assert (values["VD100|float"], values["VW20|signed"], values["VB200|string"]) == (
        23.0,
        55,
        "Line 2",
    )


async def test_values_are_written_a_quarter_of_an_hour_after_a_poll(
    hass: HomeAssistant,
    hass_storage: dict[str, Any],
    kinds_entry: MockConfigEntry,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
) -> None:
    """For a stop that writes nothing, the values are written SAVE_DELAY after a poll, and again.

    The write after the setup's poll comes SAVE_DELAY later, whatever polls since, with the
    values of the last one.
    """
    await later(hass, freezer, SAVE_DELAY - 1)
    assert storage_key(kinds_entry.entry_id) not in hass_storage
    await later(hass, freezer, 1)
    assert kept(hass_storage, kinds_entry)["VW20|signed"] == 55
    s7_smart_ha_sim.set("VW20", 70)
    await later(hass, freezer, 60)  # a poll reads it and plans the next write
    assert kept(hass_storage, kinds_entry)["VW20|signed"] == 55
    await later(hass, freezer, SAVE_DELAY)
    assert kept(hass_storage, kinds_entry)["VW20|signed"] == 70


async def test_home_assistant_keeps_no_copy_of_the_states(
    hass: HomeAssistant, kinds_entry: MockConfigEntry, freezer: FrozenDateTimeFactory
) -> None:
    """Home Assistant's restore data holds the event's state alone, before and after a restart.

    A restore entity's state is copied there, kept for the whole run and written every quarter
    of an hour: 10,000 points would cost 10,000 copies.
    """
    registry = er.async_get(hass)
    ours = {e.entity_id for e in er.async_entries_for_config_entry(registry, kinds_entry.entry_id)}
    data = restore_state.async_get(hass)
    events = {entity_id for entity_id in ours if entity_id.startswith("event.")}
    assert {s.state.entity_id for s in data.async_get_stored_states()} & ours == events
    assert await hass.config_entries.async_unload(kinds_entry.entry_id)
    await hass.async_block_till_done()
    await set_up(hass, kinds_entry)
    await poll(hass, freezer)
    assert {s.state.entity_id for s in data.async_get_stored_states()} & ours == events


async def test_a_removed_plc_leaves_no_file(
    hass: HomeAssistant, hass_storage: dict[str, Any], kinds_entry: MockConfigEntry
) -> None:
    """Removing a PLC deletes its file of values with it."""
    assert await hass.config_entries.async_unload(kinds_entry.entry_id)
    assert storage_key(kinds_entry.entry_id) in hass_storage
    await hass.config_entries.async_remove(kinds_entry.entry_id)
    await hass.async_block_till_done()
    assert storage_key(kinds_entry.entry_id) not in hass_storage


async def test_the_first_start_after_0_10_takes_its_values_from_home_assistant(
    hass: HomeAssistant,
    hass_storage: dict[str, Any],
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """0.10 stored the values with each entity's state: with no file yet, they are taken there.

    Only the entry's own entities are taken: another integration's state of the same shape
    gives nothing. Once the file exists Home Assistant's restore data is not read again.
    """
    hold(s7_smart_ha_sim, BEFORE)
    entry = await set_up(hass, make_entry(hass, s7_smart_ha_sim, [*FIRST, *KINDS]))
    ids = entity_ids(hass, entry)
    assert await hass.config_entries.async_unload(entry.entry_id)
    await hass.async_block_till_done()
    del hass_storage[storage_key(entry.entry_id)]
    mock_restore_cache_with_extra_data(
        hass,
        [
            (State(ids["temp"], "21.5"), {"values": {"VD100|float": 21.5}}),
            (State(ids["set"], "40"), {"values": {"VW20|signed": 40}}),
            (State("sensor.elsewhere", "7"), {"values": {"VW30|signed": 1}}),
        ],
    )
    paced_after_connect(monkeypatch)
    await set_up(hass, entry)
    shown = {key: hass.states.get(ids[key]) for key in ("temp", "set", "kmode")}
    assert {
        key: (state.state, state.attributes.get("restored")) for key, state in shown.items()
    } == {
        "temp": ("21.5", True),
        "set": ("40", True),
        "kmode": (STATE_UNAVAILABLE, None),
    }
    assert await hass.config_entries.async_unload(entry.entry_id)  # the file keeps them unread
    await hass.async_block_till_done()
    mock_restore_cache_with_extra_data(
        hass, [(State(ids["temp"], "99.0"), {"values": {"VD100|float": 99.0}})]
    )
    monkeypatch.setattr(S7SmartClient, "request_interval", 0.0)
    await set_up(hass, entry)
    assert hass.states.get(ids["temp"]).state == "21.5"  # type: ignore[union-attr]


async def test_event_restores_as_home_assistant_does(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """An alarm word's event entity is never marked restored: its state is its last event."""
    hold(s7_smart_ha_sim, BEFORE)
    entry = await set_up(hass, make_entry(hass, s7_smart_ha_sim, [*FIRST, *KINDS]))
    alarms = entity_ids(hass, entry)["alarms"]
    written = await restart(hass, entry, monkeypatch, freezer)
    assert all("restored" not in state.attributes for state in written[alarms])


async def test_an_edited_address_shows_no_value_of_the_old_one(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, freezer: FrozenDateTimeFactory
) -> None:
    """A point moved to another address: its entity shows no value until the new one is read.

    The entity is made anew with its id (and the state it stored at its removal), but the value
    stored is of the old address. (Unavailable states marked restored are Home Assistant's own,
    written for an entity removed while its registry entry stays.)
    """
    hold(s7_smart_ha_sim, BEFORE)
    s7_smart_ha_sim.set("VD104", 30.5, "float")
    entry = await set_up(hass, make_entry(hass, s7_smart_ha_sim, [*FIRST, *KINDS]))
    sensor = entity_ids(hass, entry)["temp"]
    written: list[State] = []

    @callback
    def note(event: Event[EventStateChangedData]) -> None:
        """Keep each state the sensor writes."""
        if (state := event.data["new_state"]) is not None and state.entity_id == sensor:
            written.append(state)

    unsubscribe = hass.bus.async_listen(EVENT_STATE_CHANGED, note)
    edit_point(hass, entry, "temp", address="VD104")
    await hass.async_block_till_done()
    await read_edits(hass, freezer)
    unsubscribe()
    shown = [state for state in written if state.state != STATE_UNAVAILABLE]
    assert [(state.state, "restored" in state.attributes) for state in shown] == [("30.5", False)]


async def test_commands_before_the_first_read_send_nothing(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A restored switch, number, select and cover take no command until their points are read.

    The poll after the setup's is held until the commands were given: the PLC gets no write.
    """
    hold(s7_smart_ha_sim, BEFORE)
    entry = await set_up(hass, make_entry(hass, s7_smart_ha_sim, [*FIRST, *KINDS]))
    ids = entity_ids(hass, entry)
    assert await hass.config_entries.async_unload(entry.entry_id)
    await hass.async_block_till_done()
    await async_mock_restore_state_shutdown_restart(hass)
    paced_after_connect(monkeypatch)
    gate, reads = asyncio.Event(), []
    read = S7SmartClient.read

    async def held(self: S7SmartClient, points: Any, **kwargs: Any) -> Any:
        """Read the setup's points; hold the reads after it until the gate opens."""
        reads.append(len(points))
        if len(reads) > 1:
            await gate.wait()
        return await read(self, points, **kwargs)

    monkeypatch.setattr(S7SmartClient, "read", held)
    await set_up(hass, entry)
    assert reads == [32]
    for key in ("pump", "set", "kmode", "shutter"):
        assert hass.states.get(ids[key]).attributes["restored"] is True  # type: ignore[union-attr]
    calls = [
        ("switch", "turn_off", ids["pump"], {}),
        ("number", "set_value", ids["set"], {"value": 10}),
        ("select", "select_option", ids["kmode"], {"option": "Off"}),
        ("cover", "set_cover_position", ids["shutter"], {"position": 0}),
    ]
    for domain, service, entity_id, data in calls:
        await hass.services.async_call(
            domain, service, {"entity_id": entity_id, **data}, blocking=True
        )
    assert s7_smart_ha_sim.calls["write"] == 0
    gate.set()
    await poll(hass, freezer)
    assert s7_smart_ha_sim.calls["write"] == 0
    assert "restored" not in hass.states.get(ids["pump"]).attributes  # type: ignore[union-attr]
