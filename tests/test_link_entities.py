"""The diagnostic entities of the link to a PLC: connectivity, and what its polls cost."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from unittest.mock import patch

from freezegun.api import FrozenDateTimeFactory
from homeassistant.const import STATE_OFF, STATE_ON, STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.helpers import entity_registry as er
from homeassistant.helpers.entity import Entity
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.plc import Point
from simulators.s7_smart import S7SmartSimulator
from tests.entries import make_entry, point, poll
from tests.runtime.test_poll_classes import reads, set_up_classes, tick

pytestmark = pytest.mark.no_pacing

__all__ = ["reads"]  # the fixture, used by name

CONNECTIVITY = "binary_sensor.s7_200_smart_connectivity"
DURATION = "sensor.s7_200_smart_poll_duration"
REQUESTS = "sensor.s7_200_smart_requests_per_poll"
FAILING = "sensor.s7_200_smart_points_failing"
LAST_POLL = "sensor.s7_200_smart_last_successful_poll"
DISABLED = (DURATION, REQUESTS, FAILING, LAST_POLL)


@contextmanager
def state_writes() -> Iterator[list[str]]:
    """Collect the entity ids whose state is written meanwhile."""
    writes: list[str] = []
    original = Entity.async_write_ha_state

    def counting(entity: Entity) -> None:
        writes.append(entity.entity_id)
        original(entity)

    with patch.object(Entity, "async_write_ha_state", counting):
        yield writes


class PollClock:
    """A perf_counter for the client whose polls take the given seconds, one after another."""

    def __init__(self, durations: list[float]) -> None:
        """Time the next polls with these durations."""
        self.durations = durations
        self.now = 0.0
        self.started = False

    def perf_counter(self) -> float:
        """Return the start of a read, then its end."""
        if self.started:
            self.now += self.durations.pop(0)
        self.started = not self.started
        return self.now


async def test_connectivity_off_while_plc_stopped(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    setup_integration: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    assert hass.states.get(CONNECTIVITY).state == STATE_ON
    await s7_smart_ha_sim.stop()
    await poll(hass, freezer)
    assert hass.states.get(CONNECTIVITY).state == STATE_OFF
    assert hass.states.get("sensor.s7_200_smart_temperature").state == STATE_UNAVAILABLE

    await s7_smart_ha_sim.start(s7_smart_ha_sim.host, s7_smart_ha_sim.port)
    await poll(hass, freezer)
    assert hass.states.get(CONNECTIVITY).state == STATE_ON


async def test_cost_sensors_disabled_by_default(
    hass: HomeAssistant, setup_integration: MockConfigEntry, entity_registry: er.EntityRegistry
) -> None:
    for entity_id in DISABLED:
        entry = entity_registry.async_get(entity_id)
        assert entry is not None, entity_id
        assert entry.disabled_by is er.RegistryEntryDisabler.INTEGRATION
        assert hass.states.get(entity_id) is None
    assert entity_registry.async_get(CONNECTIVITY).disabled_by is None


@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_link_sensors_follow_the_polls(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    setup_integration: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """A failing point counts; the last successful poll stays while the PLC is unreachable."""
    await poll(hass, freezer)
    assert hass.states.get(FAILING).state == "0"
    assert int(hass.states.get(REQUESTS).state) >= 1
    s7_smart_ha_sim.v_size = 150  # a smaller CPU: VB200 and VD300 are outside its V memory
    await poll(hass, freezer)
    assert hass.states.get(FAILING).state == "2"

    last = hass.states.get(LAST_POLL).state
    await s7_smart_ha_sim.stop()
    await poll(hass, freezer)
    assert hass.states.get(LAST_POLL).state == last
    assert hass.states.get(FAILING).state == STATE_UNAVAILABLE
    assert hass.states.get(DURATION).state == STATE_UNAVAILABLE

    await s7_smart_ha_sim.start(s7_smart_ha_sim.host, s7_smart_ha_sim.port)
    await poll(hass, freezer)
    assert hass.states.get(LAST_POLL).state > last


@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_quiet_poll_writes_no_link_state(
    hass: HomeAssistant,
    setup_integration: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Polls that change nothing write no state of the link's entities (but the last poll's)."""
    await poll(hass, freezer, 2)
    with state_writes() as writes:
        await poll(hass, freezer, 3)
    assert [e for e in writes if e in (CONNECTIVITY, DURATION, REQUESTS, FAILING)] == []
    assert writes.count(LAST_POLL) == 3


@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_requests_per_poll_quiet_over_status_reads(
    hass: HomeAssistant, s7_setup: MockConfigEntry, freezer: FrozenDateTimeFactory
) -> None:
    """The S7 reads the CPU state and clock once a minute: those polls take more requests."""
    requests = "sensor.s7_300_requests_per_poll"
    with state_writes() as writes:
        await poll(hass, freezer, 14)  # two status reads
    assert hass.states.get(requests).state == "3"
    assert requests not in writes


@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_poll_duration_ignores_noise(
    hass: HomeAssistant, setup_integration: MockConfigEntry, freezer: FrozenDateTimeFactory
) -> None:
    """Milliseconds up or down write nothing; a poll that takes much longer does."""
    clock = PollClock([0.2, 0.21, 0.19, 0.26, 0.2, 0.6, 0.65])
    with patch("custom_components.plc_bridge.plc.client.time", clock):
        await poll(hass, freezer)
        assert hass.states.get(DURATION).state == "0.2"
        with state_writes() as writes:
            await poll(hass, freezer, 4)
        assert DURATION not in writes
        await poll(hass, freezer)
        assert hass.states.get(DURATION).state == "0.6"
        with state_writes() as writes:
            await poll(hass, freezer)
        assert DURATION not in writes


class ClassClock:
    """A perf_counter for the client: a poll of one point takes 0.05 s, of more 3 s (paced)."""

    def __init__(self, reads: list[list[Point]]) -> None:
        """Time each poll by the points it reads (the last in `reads`)."""
        self.reads = reads
        self.now = 0.0
        self.started = False

    def perf_counter(self) -> float:
        """Return the start of a read, then its end."""
        if self.started:
            self.now += 3.0 if len(self.reads[-1]) > 1 else 0.05
        self.started = not self.started
        return self.now


@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_poll_duration_quiet_over_poll_classes(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    reads: list[list[Point]],
) -> None:
    """Quick polls of the fast points between long ones of every class write no duration."""
    points = [
        point("fast", "Fast", "sensor", "VW0", "signed", poll="fast"),
        point("other", "Other", "sensor", "VW2", "signed"),
    ]
    entry = make_entry(hass, s7_smart_ha_sim, points)
    await set_up_classes(hass, freezer, entry)  # fast every second, normal every 10 s
    with patch("custom_components.plc_bridge.plc.client.time", ClassClock(reads)):
        await tick(hass, freezer, 12)
        assert hass.states.get(DURATION).state == "3.0"
        with state_writes() as writes:
            await tick(hass, freezer, 25)
    assert DURATION not in writes
    assert hass.states.get(DURATION).state == "3.0"
