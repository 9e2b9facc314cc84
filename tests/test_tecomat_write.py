"""Writes to a Tecomat PLC through entity actions and the clock action, read back from it."""

from __future__ import annotations

from datetime import datetime
from zoneinfo import ZoneInfo

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.datetime import ATTR_DATETIME, DOMAIN as DATETIME_DOMAIN
from homeassistant.components.number import ATTR_VALUE, DOMAIN as NUMBER_DOMAIN, SERVICE_SET_VALUE
from homeassistant.components.switch import DOMAIN as SWITCH_DOMAIN
from homeassistant.components.text import DOMAIN as TEXT_DOMAIN
from homeassistant.const import (
    ATTR_ENTITY_ID,
    SERVICE_TURN_OFF,
    SERVICE_TURN_ON,
    STATE_OFF,
    STATE_ON,
)
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import HomeAssistantError, ServiceValidationError
from homeassistant.util import dt as dt_util
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import ATTR_CONFIG_ENTRY_ID, DOMAIN
from simulators.tecomat import TecomatSimulator
from tests.entries import poll
from tests.flows.forms import strings_at
from tests.harness import make_tecomat_entry

NUMBER = "number.fx2_cp2080_requested_temperature"
SWITCH = "switch.fx2_cp2080_circulation_pump"
TEXT = "text.fx2_cp2080_greeting"
STAMP = "datetime.fx2_cp2080_stamp"


async def settle(hass: HomeAssistant) -> None:
    """Wait for a poll that may be running still: it defers the write's refresh (debounce)."""
    await hass.async_block_till_done(wait_background_tasks=True)


async def test_number_writes_real(
    hass: HomeAssistant, tecomat_ha_sim: TecomatSimulator, tecomat_entry: MockConfigEntry
) -> None:
    """number.set_value writes the REAL of a 5.3 object; the refresh shows it."""
    await hass.services.async_call(
        NUMBER_DOMAIN,
        SERVICE_SET_VALUE,
        {ATTR_ENTITY_ID: NUMBER, ATTR_VALUE: 25.5},
        blocking=True,
    )
    await settle(hass)
    assert tecomat_ha_sim.get("Main.myObject3.value") == 25.5
    assert hass.states.get(NUMBER).state == "25.5"


async def test_switch_writes_bool(
    hass: HomeAssistant,
    tecomat_ha_sim: TecomatSimulator,
    tecomat_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """switch.turn_on and turn_off write the BOOL (the second refresh waits out the debounce)."""
    await hass.services.async_call(
        SWITCH_DOMAIN, SERVICE_TURN_ON, {ATTR_ENTITY_ID: SWITCH}, blocking=True
    )
    await settle(hass)
    assert tecomat_ha_sim.get("Main.pump.value") is True
    assert hass.states.get(SWITCH).state == STATE_ON
    await hass.services.async_call(
        SWITCH_DOMAIN, SERVICE_TURN_OFF, {ATTR_ENTITY_ID: SWITCH}, blocking=True
    )
    await settle(hass)
    assert tecomat_ha_sim.get("Main.pump.value") is False
    await poll(hass, freezer, 2)  # past the refresh debounce and a regular poll
    assert hass.states.get(SWITCH).state == STATE_OFF


async def test_text_writes_string(
    hass: HomeAssistant, tecomat_ha_sim: TecomatSimulator, tecomat_entry: MockConfigEntry
) -> None:
    """text.set_value writes the STRING with one PutObject."""
    await hass.services.async_call(
        TEXT_DOMAIN,
        SERVICE_SET_VALUE,
        {ATTR_ENTITY_ID: TEXT, ATTR_VALUE: 'Hi "there"'},
        blocking=True,
    )
    await settle(hass)
    assert tecomat_ha_sim.get("plcData.varString") == 'Hi "there"'
    assert hass.states.get(TEXT).state == 'Hi "there"'
    assert tecomat_ha_sim.calls["PutObject"] == 1


async def test_non_ascii_text_refused_before_sending(
    hass: HomeAssistant, tecomat_ha_sim: TecomatSimulator, tecomat_entry: MockConfigEntry
) -> None:
    """A STRING holds ASCII only: the vendor refuses other text, translated, sending nothing."""
    await settle(hass)
    before = tecomat_ha_sim.requests
    with pytest.raises(ServiceValidationError) as caught:
        await hass.services.async_call(
            TEXT_DOMAIN,
            SERVICE_SET_VALUE,
            {ATTR_ENTITY_ID: TEXT, ATTR_VALUE: "Grüße"},
            blocking=True,
        )
    assert caught.value.translation_domain == DOMAIN
    assert caught.value.translation_key == "invalid_value"
    assert strings_at("exceptions", "invalid_value", "message")
    assert "ASCII" in str(caught.value) or "ascii" in str(caught.value).lower()
    assert tecomat_ha_sim.requests == before
    assert tecomat_ha_sim.get("plcData.varString") == "Hello everybody"


async def test_datetime_writes_dt(
    hass: HomeAssistant, tecomat_ha_sim: TecomatSimulator, tecomat_entry: MockConfigEntry
) -> None:
    """datetime.set_value writes the DT in the PLC's (Home Assistant's) time zone."""
    when = datetime(2026, 3, 1, 12, 30, 15, tzinfo=dt_util.UTC)
    await hass.services.async_call(
        DATETIME_DOMAIN,
        SERVICE_SET_VALUE,
        {ATTR_ENTITY_ID: STAMP, ATTR_DATETIME: when},
        blocking=True,
    )
    await settle(hass)
    local = when.astimezone(ZoneInfo(hass.config.time_zone)).replace(tzinfo=None)
    assert tecomat_ha_sim.get("plcData.varDT") == local
    assert hass.states.get(STAMP).state == "2026-03-01T12:30:15+00:00"


@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_sync_clock_writes_clock_variable(
    hass: HomeAssistant, tecomat_ha_sim: TecomatSimulator, tecomat_entry: MockConfigEntry
) -> None:
    """plc_bridge.sync_clock writes Home Assistant's time into the clock variable (setTime)."""
    await hass.services.async_call(
        DOMAIN, "sync_clock", {ATTR_CONFIG_ENTRY_ID: tecomat_entry.entry_id}, blocking=True
    )
    now = dt_util.now().astimezone(ZoneInfo(hass.config.time_zone))
    written = tecomat_ha_sim.get("setTime")
    assert written.replace(microsecond=0) == now.replace(tzinfo=None, microsecond=0)
    assert tecomat_ha_sim.clock == written  # the simulated program copies it into its clock
    shown = hass.states.get("datetime.fx2_cp2080_plc_clock").state  # GetInfo asked at once
    assert shown == now.replace(microsecond=0).astimezone(dt_util.UTC).isoformat()


async def test_sync_clock_without_clock_variable(
    hass: HomeAssistant, tecomat_ha_sim: TecomatSimulator
) -> None:
    """Without a clock variable TecoApi cannot set the clock: a translated refusal."""
    entry = make_tecomat_entry(hass, tecomat_ha_sim, [])
    hass.config_entries.async_update_entry(
        entry, data={**entry.data, "vendor_options": {"auth": "digest"}}
    )
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    with pytest.raises(HomeAssistantError) as caught:
        await hass.services.async_call(
            DOMAIN, "sync_clock", {ATTR_CONFIG_ENTRY_ID: entry.entry_id}, blocking=True
        )
    assert caught.value.translation_key == "write_refused"
    assert "as the PLC's clock variable" in str(caught.value)
    assert tecomat_ha_sim.calls["PutObject"] == 0


async def test_write_action_by_address(
    hass: HomeAssistant, tecomat_ha_sim: TecomatSimulator, tecomat_entry: MockConfigEntry
) -> None:
    """plc_bridge.write sets several IEC types in one PutObject."""
    await hass.services.async_call(
        DOMAIN,
        "write",
        {
            ATTR_CONFIG_ENTRY_ID: tecomat_entry.entry_id,
            "points": [
                {"address": "plcData.varInt", "data_type": "INT", "value": -7},
                {"address": "myObject.favorites.food", "data_type": "STRING", "value": "Pizza"},
                {"address": "arr2[1][3]", "data_type": "REAL", "value": 2.5},
            ],
        },
        blocking=True,
    )
    await settle(hass)
    assert tecomat_ha_sim.calls["PutObject"] == 1
    assert tecomat_ha_sim.get("plcData.varInt") == -7
    assert tecomat_ha_sim.get("myObject.favorites.food") == "Pizza"
    assert tecomat_ha_sim.get("arr2[1][3]") == 2.5
    assert hass.states.get("sensor.fx2_cp2080_int").state == "-7"
