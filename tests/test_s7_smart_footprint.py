"""A read-only S7-200 SMART string blocks writes to its own bytes only (issue 23: a read-only
VB500 string blocked VW700 and VD704, 14 writes of 14, as if it held 255 bytes)."""

from __future__ import annotations

from homeassistant.core import HomeAssistant
from homeassistant.exceptions import ServiceValidationError
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from simulators.s7_smart import S7SmartSimulator
from tests.entries import POINTS, call, make_entry, point

pytestmark = pytest.mark.no_pacing

LABEL = point("status_text", "Status text", "sensor", "VB500", "string", read_only=True)
NAME = point("recipe_name", "Recipe name", "sensor", "VB600", "string[20]", read_only=True)


@pytest.fixture
async def string_entry(hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator) -> MockConfigEntry:
    """The simulator's entry with a read-only string the program wrote `25°C` to, and a
    read-only string declared 20 characters long."""
    s7_smart_ha_sim.strings = "raw"
    s7_smart_ha_sim.put_string("VB500", b"25\xb0C")
    s7_smart_ha_sim.put_string("VB600", b"Mix A")
    entry = make_entry(hass, s7_smart_ha_sim, [*POINTS, LABEL, NAME])
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    return entry


@pytest.mark.parametrize(
    ("address", "data_type", "point"),
    [
        ("VB503", "unsigned", "VB500"),  # the string's third character
        ("VB500", "unsigned", "VB500"),  # its length byte
        ("VW499", "signed", "VB500"),  # its length byte and first character
        ("VB620", "unsigned", "VB600"),  # within the declared 20 characters, past "Mix A"
        ("VB400", "string", "VB[56]00"),  # a string written there might reach both
    ],
)
async def test_writes_into_a_read_only_string_refused(  # noqa: PLR0917 - fixtures, parameters
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    string_entry: MockConfigEntry,
    address: str,
    data_type: str,
    point: str,
) -> None:
    """Its length byte and characters, as read or declared: refused, nothing sent."""
    before = s7_smart_ha_sim.calls["write"]
    with pytest.raises(ServiceValidationError, match=f"covers data of the read-only point {point}"):
        await call(
            hass,
            "write",
            string_entry,
            points=[{"address": address, "data_type": data_type, "value": 1}],
        )
    assert s7_smart_ha_sim.calls["write"] == before
    assert hass.states.get("sensor.s7_200_smart_status_text").state == "25°C"


async def test_writes_past_a_read_only_string_go_through(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, string_entry: MockConfigEntry
) -> None:
    """VW700 and VD704 (refused 14 of 14 before), and the byte after the declared length."""
    await call(
        hass,
        "write",
        string_entry,
        points=[
            {"address": "VW700", "data_type": "signed", "value": 700},
            {"address": "VD704", "data_type": "signed", "value": 704},
            {"address": "VB621", "data_type": "unsigned", "value": 9},
            {"address": "VB510", "data_type": "unsigned", "value": 5},
        ],
    )
    assert s7_smart_ha_sim.get("VW700") == 700
    assert s7_smart_ha_sim.get("VD704") == 704
    assert s7_smart_ha_sim.get("VB621", "unsigned") == 9
    assert s7_smart_ha_sim.get("VB510", "unsigned") == 5
