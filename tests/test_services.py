"""Tests of the actions: write, read and sync_clock."""

from __future__ import annotations

from datetime import timedelta
import hashlib
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import SOURCE_REAUTH
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import HomeAssistantError, ServiceValidationError
from homeassistant.util import dt as dt_util
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import DOMAIN
from simulators.s7_smart import DEFAULT_USER, S7SmartSimulator
from tests.entries import call

pytestmark = pytest.mark.no_pacing


async def test_write_in_one_request(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, setup_integration: MockConfigEntry
) -> None:
    points = [
        {"address": "vw30", "data_type": "signed", "value": -5},
        {"address": "VD34", "data_type": "float", "value": 1.25},
        {"address": "V40.2", "data_type": "signed", "value": True},
        {"address": "VB44", "data_type": "string", "value": "abc"},
    ]
    await call(hass, "write", setup_integration, points=points)
    assert s7_smart_ha_sim.calls["write"] == 1
    assert s7_smart_ha_sim.get("VW30") == -5
    assert s7_smart_ha_sim.get("VD34", "float") == 1.25
    assert s7_smart_ha_sim.get("V40.2") is True
    assert s7_smart_ha_sim.get("VB44", "string") == "abc"


@pytest.mark.parametrize(
    ("item", "message"),
    [
        (
            {"address": "XW1", "data_type": "signed", "value": 1},
            "Nothing was sent: 'XW1' is not an S7-200 SMART address; try V10.3, VB100, VW100, "
            "VD100, I0.0, QB0, MW4, SMB28, AIW16, T37, C10, HC0 or DATE",
        ),
        (
            {"address": "VB1", "data_type": "signed", "value": 200},
            "Nothing was sent: VB1 200 is outside -128..127",
        ),
    ],
)
async def test_write_checked_before_sending(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    setup_integration: MockConfigEntry,
    item: dict[str, Any],
    message: str,
) -> None:
    good = {"address": "VW30", "data_type": "signed", "value": 7}
    with pytest.raises(ServiceValidationError) as err:
        await call(hass, "write", setup_integration, points=[good, item])
    assert str(err.value) == message
    assert s7_smart_ha_sim.calls["write"] == 0
    assert s7_smart_ha_sim.get("VW30") == 0


async def test_write_refused_per_point(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, setup_integration: MockConfigEntry
) -> None:
    """The PLC writes what it can; the addresses it refused are named in the error."""
    s7_smart_ha_sim.v_size = 1000
    points = [
        {"address": "VW30", "data_type": "signed", "value": 7},
        {"address": "VW2000", "data_type": "signed", "value": 8},
    ]
    with pytest.raises(HomeAssistantError) as err:
        await call(hass, "write", setup_integration, points=points)
    assert str(err.value) == (
        "The PLC did not write every value: VW2000: the PLC has no such address (code 3004)"
    )
    assert s7_smart_ha_sim.get("VW30") == 7


async def test_write_auth_failure_starts_reauth(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, setup_integration: MockConfigEntry
) -> None:
    s7_smart_ha_sim._hashes[DEFAULT_USER] = hashlib.sha512(b"changed").hexdigest()
    s7_smart_ha_sim.invalidate_tokens()
    with pytest.raises(HomeAssistantError) as err:
        await call(
            hass,
            "write",
            setup_integration,
            points=[{"address": "VW30", "data_type": "signed", "value": 1}],
        )
    assert err.value.translation_key == "invalid_auth"
    assert len(list(setup_integration.async_get_active_flows(hass, {SOURCE_REAUTH}))) == 1


async def test_read(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, setup_integration: MockConfigEntry
) -> None:
    s7_smart_ha_sim.v_size = 1000
    reads = s7_smart_ha_sim.calls["read"]
    response = await call(
        hass,
        "read",
        setup_integration,
        points=[
            {"address": "vd100", "data_type": "float"},
            {"address": "VW2000", "data_type": "signed"},
            {"address": "DATE", "data_type": "signed"},
            {"address": "VD300", "data_type": "raw"},
        ],
    )
    assert response == {
        "values": {
            "VD100": 21.5,
            "VW2000": None,
            "DATE": "2026-03-01T12:30:00-08:00",
            "VD300": [1, 2, 171, 205],
        },
        "errors": {"VW2000": "VW2000: the PLC has no such address (code 3004)"},
    }
    assert s7_smart_ha_sim.calls["read"] == reads + 1


async def test_read_unreachable(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, setup_integration: MockConfigEntry
) -> None:
    await s7_smart_ha_sim.stop()
    with pytest.raises(HomeAssistantError) as err:
        await call(
            hass, "read", setup_integration, points=[{"address": "VD100", "data_type": "float"}]
        )
    assert err.value.translation_key == "communication_error"
    assert str(err.value).startswith("The PLC did not answer as expected: cannot reach 127.0.0.1")


async def test_sync_clock(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    setup_integration: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """The PLC clock is set to Home Assistant's time, in the PLC's (Home Assistant's) zone."""
    freezer.tick(timedelta(minutes=17, seconds=3))  # forward only: clients pace by this clock
    await call(hass, "sync_clock", setup_integration)
    now = dt_util.now()
    assert now.tzinfo is not None
    assert str(now.tzinfo) == "US/Pacific"
    assert s7_smart_ha_sim.clock == now.replace(microsecond=0, tzinfo=None)


async def test_sync_clock_refreshes_the_clock_point(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, setup_integration: MockConfigEntry
) -> None:
    """The PLC is polled right after its clock is set: its clock point shows the new time."""
    clock = "datetime.s7_200_smart_clock"
    assert hass.states.get(clock).state == "2026-03-01T20:30:00+00:00"
    await call(hass, "sync_clock", setup_integration)
    now = dt_util.now().replace(microsecond=0)
    assert hass.states.get(clock).state == now.astimezone(dt_util.UTC).isoformat()
    assert s7_smart_ha_sim.calls["read"] == 2


async def test_sync_clock_in_stop(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, setup_integration: MockConfigEntry
) -> None:
    s7_smart_ha_sim.mode = "STOP"
    with pytest.raises(HomeAssistantError) as err:
        await call(hass, "sync_clock", setup_integration)
    assert str(err.value) == (
        "The PLC refused the write: the PLC is in STOP; S7-200 SMART accepts writes only in RUN"
        " (CPU not in RUN., code 2001)"
    )


async def test_entry_must_exist_and_be_loaded(
    hass: HomeAssistant, setup_integration: MockConfigEntry
) -> None:
    with pytest.raises(ServiceValidationError) as err:
        await hass.services.async_call(
            DOMAIN, "sync_clock", {"config_entry_id": "nope"}, blocking=True
        )
    assert str(err.value) == "No PLC is set up with the configuration entry ID nope"

    assert await hass.config_entries.async_unload(setup_integration.entry_id)
    with pytest.raises(ServiceValidationError) as err:
        await call(hass, "sync_clock", setup_integration)
    assert str(err.value) == "The PLC S7-200 SMART is not connected right now"


async def test_user_without_write_permission(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, setup_integration: MockConfigEntry
) -> None:
    """The PLC said at connect time that its user may not write: nothing is ever sent."""
    s7_smart_ha_sim.write_permission = False
    await hass.config_entries.async_reload(setup_integration.entry_id)
    await hass.async_block_till_done()
    assert not setup_integration.runtime_data.device.can_write
    message = (
        "The PLC user Home Assistant logs in with on S7-200 SMART may not write; nothing was "
        "sent. Give that user write permission on the PLC, then reload the PLC's entry"
    )
    points = [{"address": "VW30", "data_type": "signed", "value": 1}]
    with pytest.raises(ServiceValidationError, match="may not write") as err:
        await call(hass, "write", setup_integration, points=points)
    assert str(err.value) == message
    with pytest.raises(ServiceValidationError, match="may not write"):
        await call(hass, "sync_clock", setup_integration)
    with pytest.raises(ServiceValidationError, match="may not write"):
        await hass.services.async_call(
            "switch", "turn_on", {"entity_id": "switch.s7_200_smart_pump"}, blocking=True
        )
    assert s7_smart_ha_sim.calls["write"] == 0
