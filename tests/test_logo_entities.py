"""LOGO! entities on the simulator: blocks and VM shown after one read; writes where allowed."""

from __future__ import annotations

from collections.abc import AsyncGenerator
import threading

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.number import ATTR_VALUE, SERVICE_SET_VALUE
from homeassistant.const import (
    ATTR_ENTITY_ID,
    SERVICE_TURN_OFF,
    SERVICE_TURN_ON,
    STATE_OFF,
    STATE_ON,
    STATE_UNAVAILABLE,
)
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.exceptions import HomeAssistantError, ServiceValidationError
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.plc.vendors.logo.options import DEFAULT_TSAPS
from simulators.logo import LogoSimulator
from tests.entries import add_entry, call, entry_data, point, poll, set_up, unload_all
from tests.flows.test_device_subentry_flow import add_point, new_device
from tests.harness import SNAP7_THREADS
from tests.loopback import running

GENERATIONS = ("0ba7", "0ba8", "8_x")
LOGO_8 = ("0ba8", "8_x")
POINTS = [
    point("i1", "Input 1", "binary_sensor", "I1", "BOOL"),
    point("q1", "Output 1", "binary_sensor", "Q1", "BOOL"),
    point("m1", "Flag 1", "binary_sensor", "M1", "BOOL"),
    point("ai1", "Analog 1", "sensor", "AI1", "INT"),
    point("ni1", "Network 1", "switch", "NI1", "BOOL"),
    point("setpoint", "Setpoint", "number", "VW10", "INT", min=0.0, max=1000.0, step=1.0),
    point("lamp", "Lamp", "switch", "V4.0", "BOOL"),
]
"""A machine of every block kind the LOGO! page names, plus VM (entity ids `<platform>.logo_…`)."""

INPUT = "binary_sensor.logo_input_1"
OUTPUT = "binary_sensor.logo_output_1"
FLAG = "binary_sensor.logo_flag_1"
ANALOG = "sensor.logo_analog_1"
NETWORK = "switch.logo_network_1"
SETPOINT = "number.logo_setpoint"
LAMP = "switch.logo_lamp"


@pytest.fixture(params=GENERATIONS)
async def logo(
    request: pytest.FixtureRequest, hass: HomeAssistant, freezer: FrozenDateTimeFactory
) -> AsyncGenerator[LogoSimulator]:
    """A LOGO! of each generation with the blocks of POINTS set; unloaded and stopped after."""
    sim = LogoSimulator(request.param)
    async with running(sim):
        sim.set_block("I1", True)
        sim.set_block("Q1", True)
        sim.set_block("M1", True)
        sim.set_block("AI1", 517)
        sim.set_db(1, 10, (321).to_bytes(2, "big"))  # VW10
        sim.set_db(1, 4, b"\x01")  # V4.0
        yield sim
        await unload_all(hass)
    lingering = [t.name for t in threading.enumerate() if t.name.endswith(SNAP7_THREADS)]
    assert not lingering, f"snap7 server threads left running: {lingering}"


@pytest.fixture
async def logo_entry(hass: HomeAssistant, logo: LogoSimulator) -> MockConfigEntry:
    """The LOGO!'s entry as the config flow stores it (default TSAPs), set up."""
    local, remote = DEFAULT_TSAPS[logo.generation]
    options = {"generation": logo.generation, "local_tsap": local, "remote_tsap": remote}
    entry = add_entry(
        hass,
        title="LOGO",
        entry_id=f"01JPLCBR1DGE000000LOGO{logo.generation.upper():>4}",
        unique_id=f"{logo.host}:{logo.port}",
        data=entry_data("logo", logo, ("", ""), options=options),
        points=POINTS,
    )
    return await set_up(hass, entry)


def logo_8_only(logo: LogoSimulator) -> None:
    """Skip for a 0BA7: it has no network inputs."""
    if logo.generation not in LOGO_8:
        pytest.skip("a LOGO! 0BA7 has no network inputs")


async def test_every_block_shown_after_one_read(
    hass: HomeAssistant,
    logo: LogoSimulator,
    logo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """Inputs, outputs, flags, analog values and VM show the LOGO!'s; a poll is one request.

    A 0BA7 has no NI1: that point alone fails, the others read in the same request.
    """
    network = STATE_OFF if logo.generation in LOGO_8 else STATE_UNAVAILABLE
    expected = {INPUT: STATE_ON, OUTPUT: STATE_ON, FLAG: STATE_ON, ANALOG: "517"}
    expected |= {SETPOINT: "321", LAMP: STATE_ON, NETWORK: network}
    assert {entity: hass.states.get(entity).state for entity in expected} == expected

    logo.set_block("Q1", False)
    logo.set_block("AI1", -12)
    if logo.generation in LOGO_8:
        logo.set_block("NI1", True)
    before = logo.requests, logo.calls["read"]
    await poll(hass, freezer)
    assert (logo.requests - before[0], logo.calls["read"] - before[1]) == (1, 1)
    assert hass.states.get(OUTPUT).state == STATE_OFF
    assert hass.states.get(ANALOG).state == "-12"
    assert hass.states.get(NETWORK).state == network.replace(STATE_OFF, STATE_ON)


async def test_network_input_switched_and_read_back(
    hass: HomeAssistant,
    logo: LogoSimulator,
    logo_entry: MockConfigEntry,
    freezer: FrozenDateTimeFactory,
) -> None:
    """turn_on writes NI1 and reads it back at once; its neighbours stay; turn_off clears it."""
    logo_8_only(logo)
    logo.set_block("NI2", True)
    writes, reads = logo.calls["write"], logo.calls["read"]
    await hass.services.async_call(
        "switch", SERVICE_TURN_ON, {ATTR_ENTITY_ID: NETWORK}, blocking=True
    )
    assert logo.calls["write"] - writes == 1
    assert logo.calls["read"] - reads == 2  # the read-back, then the refresh
    assert (logo.get_block("NI1"), logo.get_block("NI2")) == (True, True)
    assert hass.states.get(NETWORK).state == STATE_ON

    await hass.services.async_call(
        "switch", SERVICE_TURN_OFF, {ATTR_ENTITY_ID: NETWORK}, blocking=True
    )
    assert (logo.get_block("NI1"), logo.get_block("NI2")) == (False, True)
    await poll(hass, freezer)
    assert hass.states.get(NETWORK).state == STATE_OFF


async def test_network_input_the_program_rewrites_is_not_shown_as_written(
    hass: HomeAssistant, logo: LogoSimulator, logo_entry: MockConfigEntry
) -> None:
    """NI1 taken from another partner by the program: turn_on fails, the switch stays off."""
    logo_8_only(logo)
    logo.network_inputs = "rewritten"
    logo.set_block("NI1", False, by_program=True)
    with pytest.raises(HomeAssistantError) as failed:
        await hass.services.async_call(
            "switch", SERVICE_TURN_ON, {ATTR_ENTITY_ID: NETWORK}, blocking=True
        )
    assert failed.value.translation_key == "write_failed"
    assert "does not take this network input" in str(failed.value)
    assert logo.get_block("NI1") is False
    assert hass.states.get(NETWORK).state == STATE_OFF


async def test_vm_switch_and_number_land_in_vm(
    hass: HomeAssistant, logo: LogoSimulator, logo_entry: MockConfigEntry
) -> None:
    """A number sets VW10 as a big-endian INT, a switch V4.0 alone: the bytes around stay."""
    logo.set_db(1, 9, b"\x11")
    logo.set_db(1, 12, b"\x22")
    logo.set_db(1, 4, b"\xa0")  # V4.5 and V4.7 on, V4.0 off
    await hass.services.async_call(
        "number", SERVICE_SET_VALUE, {ATTR_ENTITY_ID: SETPOINT, ATTR_VALUE: 730}, blocking=True
    )
    assert logo.get_db(1, 9, 4) == b"\x11\x02\xda\x22"
    assert hass.states.get(SETPOINT).state == "730"
    await hass.services.async_call("switch", SERVICE_TURN_ON, {ATTR_ENTITY_ID: LAMP}, blocking=True)
    assert logo.get_db(1, 4, 1) == b"\xa1"


async def test_output_write_refused_before_sending(
    hass: HomeAssistant, logo: LogoSimulator, logo_entry: MockConfigEntry
) -> None:
    """The write action on Q1 is refused with the translated error; the LOGO! sees no write."""
    requests, writes = logo.requests, logo.calls["write"]
    with pytest.raises(ServiceValidationError) as refused:
        await call(
            hass, "write", logo_entry, points=[{"address": "Q1", "data_type": "BOOL", "value": 0}]
        )
    assert refused.value.translation_key == "address_not_writable"
    assert str(refused.value) == (
        "Q1 can never be written (an input or a read-only area of the PLC); nothing was sent"
    )
    assert (logo.requests, logo.calls["write"]) == (requests, writes)
    assert logo.get_block("Q1") is True


async def test_forms_and_actions_know_the_generation(
    hass: HomeAssistant, logo: LogoSimulator, logo_entry: MockConfigEntry
) -> None:
    """A block the configured generation lacks is refused on the form's address field and by
    the read action, before anything is sent; a block it has is taken."""
    lacks = logo.generation not in LOGO_8  # a 0BA7 has no network inputs
    menu = await new_device(hass, logo_entry)
    result = await add_point(
        hass, menu, {"name": "Partner", "platform": "switch", "address": "NI2", "data_type": "BOOL"}
    )
    if lacks:
        assert result["errors"] == {"address": "invalid_address"}
        assert "this LOGO! generation has none" in result["description_placeholders"]["error"]
    else:
        assert result["type"] is FlowResultType.MENU
    requests = logo.requests
    point = {"address": "NI2", "data_type": "BOOL"}
    if lacks:
        with pytest.raises(ServiceValidationError) as refused:
            await call(hass, "read", logo_entry, points=[point])
        assert refused.value.translation_key == "invalid_address"
        assert logo.requests == requests
    else:
        await call(hass, "read", logo_entry, points=[point])
