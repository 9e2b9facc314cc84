"""S7 point subentries: the S7 address parser checks the form, its words on the address field."""

from __future__ import annotations

from typing import Any

from homeassistant.config_entries import SOURCE_USER
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import SUBENTRY_POINT
from custom_components.plc_bridge.plc.vendors.s7 import S7Client
from simulators.s7 import S7Simulator
from tests.flow_fixtures import error_message, translated

from .s7_ha_fixtures import make_s7_entry

POINTS = ("config_subentries", SUBENTRY_POINT)


def point_input(**changes: Any) -> dict[str, Any]:
    """Return the point form input of an INT sensor in DB1, with changes."""
    values = {
        "name": "Level",
        "platform": "sensor",
        "address": "db1.dbw2",
        "data_type": "INT",
        "scale": 1,
        "offset": 0,
        "read_only": True,
    }
    return values | changes


@pytest.fixture
def entry(hass: HomeAssistant, s7_ha_sim: S7Simulator) -> MockConfigEntry:
    """An S7 entry without points (not set up: the form needs no connection)."""
    return make_s7_entry(hass, s7_ha_sim, [])


async def add(hass: HomeAssistant, entry: MockConfigEntry, values: dict[str, Any]) -> Any:
    """Open the point form and submit it; check both answers are translated."""
    result = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_POINT), context={"source": SOURCE_USER}
    )
    translated(result, *POINTS)
    result = await hass.config_entries.subentries.async_configure(result["flow_id"], values)
    return translated(result, *POINTS)


async def test_types_offered(hass: HomeAssistant, entry: MockConfigEntry) -> None:
    """The type selector offers the S7 types and takes custom ones (STRING[n])."""
    result = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_POINT), context={"source": SOURCE_USER}
    )
    config = result["data_schema"].schema["data_type"].config
    assert config["options"] == list(S7Client.data_types)
    assert config["custom_value"] is True


@pytest.mark.parametrize(
    ("address", "data_type"),
    [
        ("DB1.DBW4", "REAL"),
        ("XYZ1", "INT"),
        ("M10.8", "BOOL"),
        ("DB0.DBW0", "INT"),
        ("DB1.DBB10", "STRING[300]"),
    ],
)
async def test_invalid_address_refused(
    hass: HomeAssistant, entry: MockConfigEntry, address: str, data_type: str
) -> None:
    """The parser's message is the address field's error; nothing is stored."""
    result = await add(hass, entry, point_input(address=address, data_type=data_type))
    assert result["type"] is FlowResultType.FORM
    assert result["errors"] == {"address": "invalid_address"}
    message = error_message(result, "address", *POINTS)
    assert message.startswith("Invalid address: ")
    assert address in message or data_type == "STRING[300]"
    assert not entry.subentries


async def test_parser_messages(hass: HomeAssistant, entry: MockConfigEntry) -> None:
    """The messages say what to write instead."""
    result = await add(hass, entry, point_input(address="DB1.DBW4", data_type="REAL"))
    assert error_message(result, "address", *POINTS) == (
        "Invalid address: DB1.DBW4 is a word (16 bits) for WORD, INT or UINT; for REAL use DB1.DBD4"
    )
    result = await add(hass, entry, point_input(address="M10.8", data_type="BOOL"))
    assert error_message(result, "address", *POINTS) == (
        "Invalid address: 'M10.8': bit numbers run from 0 to 7"
    )
    result = await add(hass, entry, point_input(address="XYZ1"))
    assert error_message(result, "address", *POINTS).startswith(
        "Invalid address: 'XYZ1' is not an S7 address; try DB1.DBX0.0"
    )


async def test_string_with_length_accepted(hass: HomeAssistant, entry: MockConfigEntry) -> None:
    """STRING[20], typed into the selector, is stored normalized."""
    result = await add(
        hass,
        entry,
        point_input(name="Recipe", address=" db1.dbb10 ", data_type="string[20]"),
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    (subentry,) = entry.subentries.values()
    assert subentry.unique_id == "DB1.DBB10|STRING[20]"
    assert subentry.data["address"] == "DB1.DBB10"
    assert subentry.data["data_type"] == "STRING[20]"


@pytest.mark.parametrize(
    "case",
    [
        ("switch", "DB1.DBW2", "INT", "needs_bool"),
        ("number", "DB1.DBX0.0", "BOOL", "needs_number"),
        ("number", "DB1.DBB10", "STRING[20]", "needs_number"),
    ],
)
async def test_platform_fits_type(
    hass: HomeAssistant, entry: MockConfigEntry, case: tuple[str, str, str, str]
) -> None:
    """A platform is refused for a point whose values it cannot show."""
    platform, address, data_type, error = case
    result = await add(
        hass, entry, point_input(platform=platform, address=address, data_type=data_type)
    )
    assert result["errors"] == {"platform": error}


async def test_bit_and_number_points_added(hass: HomeAssistant, entry: MockConfigEntry) -> None:
    """A switch on M10.1 and a number on DB1.DBW4 with limits are stored as typed."""
    result = await add(
        hass,
        entry,
        point_input(name="Pump", platform="switch", address="m10.1", data_type="BOOL"),
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    values = point_input(name="Setpoint", platform="number", address="DB1.DBW4", min=0, max=100)
    result = await add(hass, entry, values | {"read_only": False})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    stored = {sub.unique_id: dict(sub.data) for sub in entry.subentries.values()}
    assert stored["M10.1|BOOL"]["platform"] == "switch"
    assert stored["DB1.DBW4|INT"]["min"] == 0.0
    assert stored["DB1.DBW4|INT"]["max"] == 100.0
