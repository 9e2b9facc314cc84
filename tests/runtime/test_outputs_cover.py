"""Level commands of covers and valves: interlocked, released at the end, on time, at unload.

Run against the S7-200 SMART and TecoApi simulators, with HA's time travel and write faults.
"""

from __future__ import annotations

from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.cover import (
    ATTR_POSITION,
    DOMAIN as COVER_DOMAIN,
    SERVICE_CLOSE_COVER,
    SERVICE_OPEN_COVER,
    SERVICE_SET_COVER_POSITION,
    SERVICE_STOP_COVER,
)
from homeassistant.components.valve import (  # type: ignore[attr-defined]
    DOMAIN as VALVE_DOMAIN,
)
from homeassistant.const import (
    ATTR_ENTITY_ID,
    EVENT_HOMEASSISTANT_STOP,
    SERVICE_CLOSE_VALVE,
    SERVICE_OPEN_VALVE,
)
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import HomeAssistantError
from homeassistant.helpers import issue_registry as ir
import pytest

from custom_components.plc_bridge.const import DOMAIN
from custom_components.plc_bridge.cover import DEFAULT_TRAVEL_TIME, STOP_HOLD
from tests.entries import SCAN_INTERVAL
from tests.harness import OUTPUT_FAMILIES, Faults, PlcUnderTest, wait

pytestmark = [
    pytest.mark.no_pacing,
    pytest.mark.parametrize("plc", OUTPUT_FAMILIES, indirect=True),
    pytest.mark.usefixtures("outputs_at_rest"),
]

COMMANDS = ("open", "close", "stop")


async def act(
    hass: HomeAssistant, plc: PlcUnderTest, service: str, domain: str = COVER_DOMAIN
) -> None:
    """Call a cover (or valve) action on the test entity."""
    await hass.services.async_call(
        domain, service, {ATTR_ENTITY_ID: plc.entity(domain)}, blocking=True
    )


def held(plc: PlcUnderTest) -> tuple[bool, ...]:
    """What the PLC holds at the open, close and stop commands."""
    return tuple(plc.get(role) for role in COMMANDS)


def cover(plc: PlcUnderTest, *roles: str, **extra: Any) -> list[Any]:
    """The parts of the test cover: level commands and the given end-position parts."""
    return [plc.part(role, **extra) for role in (*COMMANDS, *roles)]


async def test_open_close_stop_never_both(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    plc: PlcUnderTest,
    faults: Faults,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Each command releases the others in its own write; a level stop ends after its hold."""
    entry = await plc.set_up(hass, cover(plc))
    faults.wrap(entry.runtime_data.client, monkeypatch)
    await act(hass, plc, SERVICE_CLOSE_COVER)
    assert held(plc) == (False, True, False)
    await act(hass, plc, SERVICE_OPEN_COVER)
    assert held(plc) == (True, False, False)
    await act(hass, plc, SERVICE_STOP_COVER)
    assert held(plc) == (False, False, True)
    await wait(hass, freezer, STOP_HOLD + 0.1)
    assert held(plc) == (False, False, False)
    await act(hass, plc, SERVICE_CLOSE_COVER)
    assert held(plc) == (False, True, False)
    assert len(faults.writes[0][0]) == 3  # on and the two releases, in one write
    assert all(urgent for _, urgent in faults.writes)
    assert faults.both == []


@pytest.mark.parametrize("end", ["limit", "position", "status"])
async def test_released_at_the_end_position(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, plc: PlcUnderTest, end: str
) -> None:
    """Open is released once a poll reads the open end, close at the closed end."""
    parts = {
        "limit": cover(plc, "open_limit", "closed_limit"),
        "position": cover(plc, "position"),
        "status": cover(plc, "status", value_map="0=closed;1=opening;2=open;3=closing"),
    }[end]
    if end == "position":
        parts[-1] = plc.part("position", read_only=True)
    await plc.set_up(hass, parts)
    await act(hass, plc, SERVICE_OPEN_COVER)
    await wait(hass, freezer, SCAN_INTERVAL)
    assert held(plc) == (True, False, False)
    if end == "limit":
        plc.set("open_limit", True)
    else:
        plc.set(end, 100 if end == "position" else 2)
    await wait(hass, freezer, SCAN_INTERVAL)
    await wait(hass, freezer, 0)
    assert held(plc) == (False, False, False)
    await act(hass, plc, SERVICE_CLOSE_COVER)
    if end == "limit":
        plc.set("open_limit", False)
        plc.set("closed_limit", True)
    else:
        plc.set(end, 0)
    await wait(hass, freezer, SCAN_INTERVAL)
    await wait(hass, freezer, 0)
    assert held(plc) == (False, False, False)


async def test_end_read_before_the_command_is_no_end(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, plc: PlcUnderTest
) -> None:
    """A closed limit still read from before the command releases close only when read again.

    Opened and closed again before a poll: the limit still shows closed until it is read left.
    """
    plc.set("closed_limit", True)
    await plc.set_up(hass, cover(plc, "closed_limit"))
    await act(hass, plc, SERVICE_OPEN_COVER)
    await act(hass, plc, SERVICE_CLOSE_COVER)
    await wait(hass, freezer, 0.5)
    assert held(plc) == (False, True, False)
    plc.set("closed_limit", False)
    await wait(hass, freezer, SCAN_INTERVAL)
    assert held(plc) == (False, True, False)
    plc.set("closed_limit", True)
    await wait(hass, freezer, SCAN_INTERVAL)
    await wait(hass, freezer, 0)
    assert held(plc) == (False, False, False)


async def test_closed_already_is_released_by_the_next_poll(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, plc: PlcUnderTest
) -> None:
    """Closing a cover that is closed: a poll an interval later still reads closed: released."""
    plc.set("closed_limit", True)
    await plc.set_up(hass, cover(plc, "closed_limit"))
    await act(hass, plc, SERVICE_CLOSE_COVER)
    assert held(plc) == (False, True, False)
    await wait(hass, freezer, SCAN_INTERVAL)
    await wait(hass, freezer, 0)
    assert held(plc) == (False, False, False)


@pytest.mark.parametrize(("travel_time", "after"), [(5, 5.0), (None, DEFAULT_TRAVEL_TIME)])
async def test_released_after_the_travel_time(
    hass: HomeAssistant,
    freezer: FrozenDateTimeFactory,
    plc: PlcUnderTest,
    travel_time: int | None,
    after: float,
) -> None:
    """Without an end read, open is released after the travel time set, else the default."""
    extra = {} if travel_time is None else {"travel_time": travel_time}
    await plc.set_up(hass, [plc.part("open", **extra), plc.part("close")])
    await act(hass, plc, SERVICE_OPEN_COVER)
    await wait(hass, freezer, after - 1)  # the harness fires timers up to 0.5 s early
    assert plc.get("open") is True
    await wait(hass, freezer, 1.1)
    assert plc.get("open") is False


@pytest.mark.parametrize("how", ["unload", "stop"])
async def test_released_at_unload_and_stop(
    hass: HomeAssistant,
    plc: PlcUnderTest,
    faults: Faults,
    monkeypatch: pytest.MonkeyPatch,
    how: str,
) -> None:
    """A level command still held is released when the entry unloads or Home Assistant stops."""
    entry = await plc.set_up(hass, cover(plc))
    faults.wrap(entry.runtime_data.client, monkeypatch)
    await act(hass, plc, SERVICE_OPEN_COVER)
    assert plc.get("open") is True
    if how == "unload":
        assert await hass.config_entries.async_unload(entry.entry_id)
    else:
        hass.bus.async_fire(EVENT_HOMEASSISTANT_STOP)
        await hass.async_block_till_done()
    assert held(plc) == (False, False, False)
    assert faults.writes[-1] == ({plc.addresses["open"]: False if plc.bit == "BOOL" else 0}, True)


@pytest.mark.parametrize("fault", ["lost_answer", "dropped"])
async def test_open_that_failed_is_still_released(
    hass: HomeAssistant,
    *,
    freezer: FrozenDateTimeFactory,
    plc: PlcUnderTest,
    faults: Faults,
    monkeypatch: pytest.MonkeyPatch,
    fault: str,
) -> None:
    """An open whose write failed may have landed: it is released after its travel time."""
    entry = await plc.set_up(hass, [plc.part("open", travel_time=5), plc.part("close")])
    faults.wrap(entry.runtime_data.client, monkeypatch)
    faults.queue.append(fault)
    with pytest.raises(HomeAssistantError):
        await act(hass, plc, SERVICE_OPEN_COVER)
    assert plc.get("open") is (fault == "lost_answer")
    await wait(hass, freezer, 5.1)
    assert plc.get("open") is False
    assert faults.sent("open")[-1] in (False, 0)


async def test_release_retried_until_confirmed(
    hass: HomeAssistant,
    *,
    freezer: FrozenDateTimeFactory,
    plc: PlcUnderTest,
    faults: Faults,
    monkeypatch: pytest.MonkeyPatch,
    issue_registry: ir.IssueRegistry,
    caplog: pytest.LogCaptureFixture,
) -> None:
    """A release the PLC does not confirm is retried with back-off; an issue names it meanwhile."""
    entry = await plc.set_up(hass, [plc.part("open", travel_time=5), plc.part("close")])
    faults.wrap(entry.runtime_data.client, monkeypatch)
    issue = f"command_not_released_{entry.entry_id}_shutter_close_open"  # group key, role
    await act(hass, plc, SERVICE_OPEN_COVER)
    faults.queue.extend(["dropped", "lost_answer", "dropped"])
    await wait(hass, freezer, 5.1)
    assert plc.get("open") is True
    assert issue_registry.async_get_issue(DOMAIN, issue) is not None
    with pytest.raises(HomeAssistantError, match="not released yet"):
        await act(hass, plc, SERVICE_OPEN_COVER)
    await wait(hass, freezer, 1.1)  # the second try lands, its answer is lost
    assert plc.get("open") is False
    assert issue_registry.async_get_issue(DOMAIN, issue) is not None
    await wait(hass, freezer, 2.1)  # the third is dropped
    await wait(hass, freezer, 4.1)  # the fourth is confirmed
    assert issue_registry.async_get_issue(DOMAIN, issue) is None
    assert len(faults.sent("open")) == 5
    assert caplog.text.count("could not be released") == 1
    await act(hass, plc, SERVICE_OPEN_COVER)
    assert plc.get("open") is True


async def test_position_write_releases_held_commands(
    hass: HomeAssistant, plc: PlcUnderTest, faults: Faults, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Moving to a position releases the level command still held, in the same write."""
    setter = plc.part("position")
    entry = await plc.set_up(hass, [*cover(plc), setter])
    faults.wrap(entry.runtime_data.client, monkeypatch)
    await act(hass, plc, SERVICE_OPEN_COVER)
    await hass.services.async_call(
        COVER_DOMAIN,
        SERVICE_SET_COVER_POSITION,
        {ATTR_ENTITY_ID: plc.entity("cover"), ATTR_POSITION: 40},
        blocking=True,
    )
    assert (plc.get("position"), plc.get("open")) == (40, False)
    assert set(faults.writes[-1][0]) == {plc.addresses["position"], plc.addresses["open"]}


async def test_valve_with_a_position_sends_its_commands(
    hass: HomeAssistant, plc: PlcUnderTest, faults: Faults, monkeypatch: pytest.MonkeyPatch
) -> None:
    """open_valve and close_valve send the commands, not 100 % and 0 % to the position."""
    parts = [
        plc.part(role, name="Inlet", platform="valve") for role in ("open", "close", "position")
    ]
    entry = await plc.set_up(hass, parts)
    faults.wrap(entry.runtime_data.client, monkeypatch)
    await hass.services.async_call(
        VALVE_DOMAIN, SERVICE_OPEN_VALVE, {ATTR_ENTITY_ID: plc.entity("valve", "inlet")}, True
    )
    assert (plc.get("open"), plc.get("close"), plc.get("position")) == (True, False, 0)
    await hass.services.async_call(
        VALVE_DOMAIN, SERVICE_CLOSE_VALVE, {ATTR_ENTITY_ID: plc.entity("valve", "inlet")}, True
    )
    assert (plc.get("open"), plc.get("close"), plc.get("position")) == (False, True, 0)
    assert faults.sent("position") == []
