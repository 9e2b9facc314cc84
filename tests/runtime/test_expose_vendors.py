"""Exposes on every vendor: Home Assistant states written to the simulator, bursts batched."""

from __future__ import annotations

import math
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.const import STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.helpers import issue_registry as ir
import pytest

from custom_components.plc_bridge.const import DOMAIN
from custom_components.plc_bridge.runtime.expose import FAILURE_LIMIT
from custom_components.plc_bridge.runtime.issues import expose_issue_id
from tests.entries import set_up
from tests.harness import PlcUnderTest, add_expose, burst, settle, shown

pytestmark = pytest.mark.no_pacing

OUTDOOR = "sensor.outdoor_temperature"
PRESENCE = "person.anna"
SUN = "sun.sun"


def shown_entity(title: str) -> str:
    """Return the entity id of the `shown` sensor of a PLC with this title."""
    return f"sensor.{title.lower().replace(' ', '_').replace('-', '_')}_shown"


def near(held: Any, value: float) -> bool:
    """True when a REAL the PLC holds is the value (single precision)."""
    return math.isclose(float(held), value, rel_tol=1e-6)


async def test_state_change_written(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, every_plc: PlcUnderTest
) -> None:
    """A temperature, an attribute and a presence (value map) reach the PLC; polled: shown."""
    plc = every_plc
    hass.states.async_set(OUTDOOR, "3.5")
    hass.states.async_set(PRESENCE, "not_home")
    hass.states.async_set(SUN, "above_horizon", {"azimuth": 120})
    entry = plc.entry(hass, [shown(plc)])
    add_expose(hass, entry, OUTDOOR, plc.family.real)
    add_expose(hass, entry, PRESENCE, plc.family.flag, value_map="home=1;not_home=0")
    add_expose(hass, entry, SUN, plc.family.burst[1], attribute="azimuth")
    await set_up(hass, entry)
    writes = plc.writes()
    hass.states.async_set(OUTDOOR, "21.5")
    hass.states.async_set(PRESENCE, "home")
    hass.states.async_set(SUN, "above_horizon", {"azimuth": 121})
    await settle(hass, freezer)
    assert near(plc.read(*plc.family.real), 21.5)
    assert plc.read(*plc.family.flag) in (True, 1)
    assert plc.read(*plc.family.burst[1]) == 121
    assert hass.states.get(shown_entity(entry.title)).state == "21.5"
    hass.states.async_set(PRESENCE, "not_home")
    await settle(hass, freezer, 1.0)  # past the cooldown
    assert plc.read(*plc.family.flag) in (False, 0)
    assert plc.writes() > writes


async def test_unavailable_writes_nothing_or_the_default(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, every_plc: PlcUnderTest
) -> None:
    """An unavailable entity writes nothing, or the expose's default where it has one."""
    plc = every_plc
    hass.states.async_set(OUTDOOR, "4.5")
    hass.states.async_set(PRESENCE, "home")
    entry = plc.entry(hass, [shown(plc)])
    add_expose(hass, entry, OUTDOOR, plc.family.real, send_on_start=True)
    add_expose(
        hass, entry, PRESENCE, plc.family.burst[0], default="7", value_map="home=1;not_home=0"
    )
    await set_up(hass, entry)
    await settle(hass, freezer)
    assert near(plc.read(*plc.family.real), 4.5)
    writes = plc.writes()
    hass.states.async_set(OUTDOOR, STATE_UNAVAILABLE)
    await settle(hass, freezer, 2.0)
    assert plc.writes() == writes
    assert near(plc.read(*plc.family.real), 4.5)
    hass.states.async_set(PRESENCE, STATE_UNAVAILABLE)
    await settle(hass, freezer, 2.0)
    assert plc.read(*plc.family.burst[0]) == 7


async def test_burst_costs_the_minimum_requests(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, every_plc: PlcUnderTest
) -> None:
    """Ten exposes changed at once go out in the vendor's fewest write requests (one)."""
    plc = every_plc
    _, cost = await burst(hass, freezer, plc)
    assert cost.held == cost.sent == list(range(11, 21))
    assert cost.writes == 1
    # Tecomat reads the written variables back (a PutObject's 204 proves nothing): one more.
    assert cost.requests == (2 if plc.vendor == "tecomat" else 1)


async def test_send_on_start_after_a_restart(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, every_plc: PlcUnderTest
) -> None:
    """The current state is written at setup, and again at the next setup (a restart)."""
    plc = every_plc
    hass.states.async_set(OUTDOOR, "4.5")
    entry = plc.entry(hass, [shown(plc)])
    add_expose(hass, entry, OUTDOOR, plc.family.real, send_on_start=True)
    await set_up(hass, entry)
    await settle(hass, freezer)
    assert near(plc.read(*plc.family.real), 4.5)
    assert await hass.config_entries.async_unload(entry.entry_id)
    hass.states.async_set(OUTDOOR, "6.5")
    await settle(hass, freezer, 2.0)
    assert near(plc.read(*plc.family.real), 4.5)  # not loaded: nothing written
    await set_up(hass, entry)
    await settle(hass, freezer)
    assert near(plc.read(*plc.family.real), 6.5)


async def test_value_out_of_range_refused(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    every_plc: PlcUnderTest,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """A value no REAL holds is refused before sending, logged once; nothing is written."""
    plc = every_plc
    hass.states.async_set(OUTDOOR, "1.5")
    entry = plc.entry(hass, [shown(plc)])
    add_expose(hass, entry, OUTDOOR, plc.family.real)
    await set_up(hass, entry)
    writes = plc.writes()
    for value in ("1e39", "-1e39"):
        hass.states.async_set(OUTDOOR, value)
        await settle(hass, freezer, 2.0)
    assert plc.writes() == writes
    assert len([r for r in caplog.records if "nothing sent" in r.message]) == 1


async def test_lost_plc_raises_an_issue_cleared_when_back(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    every_plc: PlcUnderTest,
    issue_registry: ir.IssueRegistry,
) -> None:
    """Writes to a PLC that is gone fail; an issue after a few in a row, gone once one works."""
    plc = every_plc
    hass.states.async_set(OUTDOOR, "1.5")
    entry = plc.entry(hass, [shown(plc)])
    subentry_id = add_expose(hass, entry, OUTDOOR, plc.family.real)
    await set_up(hass, entry)
    issue = expose_issue_id(entry, subentry_id)
    await plc.sim.stop()
    for index in range(FAILURE_LIMIT):
        assert issue_registry.async_get_issue(DOMAIN, issue) is None
        hass.states.async_set(OUTDOOR, str(2.5 + index))
        await settle(hass, freezer, 2.0)
    assert issue_registry.async_get_issue(DOMAIN, issue) is not None
    await plc.sim.start(plc.sim.host, plc.sim.port)
    await settle(hass, freezer, 10.0)  # past any reconnect wait, and a poll
    hass.states.async_set(OUTDOOR, "9.5")
    await settle(hass, freezer, 2.0)
    assert near(plc.read(*plc.family.real), 9.5)
    assert issue_registry.async_get_issue(DOMAIN, issue) is None
