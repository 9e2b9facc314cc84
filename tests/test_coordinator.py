"""Tests of the coordinator: one planned read per poll, per-point failures, recovery, sessions."""

from __future__ import annotations

import hashlib
import logging
import math

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import SOURCE_REAUTH, ConfigEntryState
from homeassistant.const import CONF_SCAN_INTERVAL, STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.helpers import issue_registry as ir
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import DOMAIN
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from simulators.s7_smart import DEFAULT_USER, S7SmartSimulator
from tests.entries import make_entry, point, poll

pytestmark = pytest.mark.no_pacing


def words(count: int) -> list:
    """Return `count` sensor points on consecutive V words."""
    return [
        point(f"word{index}", f"Word {index}", "sensor", f"VW{2 * index}", "signed")
        for index in range(count)
    ]


@pytest.mark.parametrize("count", [1, 32, 33, 100])
async def test_one_read_per_32_points(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    freezer: FrozenDateTimeFactory,
    count: int,
) -> None:
    entry = make_entry(hass, s7_smart_ha_sim, words(count))
    assert await hass.config_entries.async_setup(entry.entry_id)
    before = s7_smart_ha_sim.calls["read"]
    await poll(hass, freezer)
    assert s7_smart_ha_sim.calls["read"] - before == math.ceil(count / 32)
    assert entry.runtime_data.client.metrics.last_poll_requests == math.ceil(count / 32)
    # and the operating mode and the clock drift
    assert len(hass.states.async_entity_ids("sensor")) == count + 2


async def test_points_read_once(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, freezer: FrozenDateTimeFactory
) -> None:
    """Two entities of one address are one node: 33 entities, 32 addresses, one request."""
    twin = point("twin", "Twin", "sensor", "VW0", "signed")
    entry = make_entry(hass, s7_smart_ha_sim, [*words(32), twin])
    assert await hass.config_entries.async_setup(entry.entry_id)
    before = s7_smart_ha_sim.calls["read"]
    await poll(hass, freezer)
    assert s7_smart_ha_sim.calls["read"] - before == 1


async def test_failing_point_alone_unavailable_logged_once(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    setup_integration: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    caplog: pytest.LogCaptureFixture,
) -> None:
    caplog.set_level(logging.INFO)
    s7_smart_ha_sim.v_size = 150  # a smaller CPU: VB200 and VD300 are outside its V memory
    await poll(hass, freezer, times=3)
    assert hass.states.get("sensor.s7_200_smart_label").state == STATE_UNAVAILABLE
    assert hass.states.get("sensor.s7_200_smart_raw").state == STATE_UNAVAILABLE
    assert hass.states.get("sensor.s7_200_smart_temperature").state == "21.5"
    assert hass.states.get("number.s7_200_smart_setpoint").state == "30"
    warnings = [r for r in caplog.records if "cannot read VB200" in r.getMessage()]
    assert len(warnings) == 1
    assert warnings[0].levelno == logging.WARNING
    assert "the PLC has no such address (code 3004)" in warnings[0].getMessage()

    s7_smart_ha_sim.v_size = 20480
    await poll(hass, freezer, times=2)
    assert hass.states.get("sensor.s7_200_smart_label").state == "Line 1"
    assert len([r for r in caplog.records if "VB200 (string) can be read again" in r.message]) == 1


async def test_unavailable_while_plc_restarts(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    setup_integration: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    await s7_smart_ha_sim.stop()
    await poll(hass, freezer)
    assert hass.states.get("sensor.s7_200_smart_temperature").state == STATE_UNAVAILABLE
    assert hass.states.get("sensor.s7_200_smart_operating_mode").state == STATE_UNAVAILABLE

    s7_smart_ha_sim.set("VD100", 22.0, "float")
    await s7_smart_ha_sim.start(s7_smart_ha_sim.host, s7_smart_ha_sim.port)
    await poll(hass, freezer)
    assert hass.states.get("sensor.s7_200_smart_temperature").state == "22.0"
    assert hass.states.get("sensor.s7_200_smart_operating_mode").state == "run"


async def test_session_conflict_issue(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    setup_integration: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
    issue_registry: ir.IssueRegistry,
) -> None:
    """Another client logging in with the same user ends our session before every poll."""
    issue_id = f"session_conflict_{setup_integration.entry_id}"
    for _ in range(3):
        s7_smart_ha_sim.invalidate_tokens()
        await poll(hass, freezer)
    assert hass.states.get("sensor.s7_200_smart_temperature").state == "21.5"
    assert setup_integration.runtime_data.client.metrics.session_renewals == 3
    assert issue_registry.async_get_issue(DOMAIN, issue_id) is not None

    await poll(hass, freezer, times=9)
    assert issue_registry.async_get_issue(DOMAIN, issue_id) is not None
    await poll(hass, freezer)
    assert issue_registry.async_get_issue(DOMAIN, issue_id) is None


async def test_auth_failure_while_polling_starts_reauth(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    setup_integration: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    s7_smart_ha_sim._hashes[DEFAULT_USER] = hashlib.sha512(b"changed").hexdigest()
    s7_smart_ha_sim.invalidate_tokens()
    await poll(hass, freezer)
    assert hass.states.get("sensor.s7_200_smart_temperature").state == STATE_UNAVAILABLE
    flows = setup_integration.async_get_active_flows(hass, {SOURCE_REAUTH})
    assert len(list(flows)) == 1


async def test_malformed_reply_makes_poll_fail(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    setup_integration: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    s7_smart_ha_sim.malformed = True
    await poll(hass, freezer)
    coordinator = setup_integration.runtime_data.coordinator
    assert not coordinator.last_update_success
    assert str(coordinator.last_exception).startswith("The PLC did not answer as expected: ")


@pytest.mark.parametrize(
    ("options", "pace"),
    [
        ({}, (0.0, 10.0)),  # the vendor's default
        ({CONF_SCAN_INTERVAL: 2.5}, (0.0, 2.5)),
        ({CONF_SCAN_INTERVAL: 2.0}, (1.0, 4.0)),  # 100 points are 4 requests a second apart
    ],
)
async def test_poll_interval(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    monkeypatch: pytest.MonkeyPatch,
    options: dict[str, float],
    pace: tuple[float, float],
) -> None:
    """The interval: the user's, else the vendor's default, never faster than its pacing."""
    request_interval, expected = pace
    entry = make_entry(hass, s7_smart_ha_sim, words(100))
    hass.config_entries.async_update_entry(entry, options=options)
    # Only the coordinator's arithmetic is under test: no request is made at this pace.
    monkeypatch.setattr(
        S7SmartClient,
        "min_scan_interval",
        classmethod(lambda cls, points: request_interval * cls.requests_for(points)),
    )
    assert await hass.config_entries.async_setup(entry.entry_id)
    assert entry.state is ConfigEntryState.LOADED
    assert entry.runtime_data.coordinator.update_interval.total_seconds() == expected
