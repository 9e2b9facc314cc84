"""Point subentries of a vendor that lists its variables: pick one, the form is filled in.

No vendor with `can_browse` is written yet: these tests register FakeClient as one.
"""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

from homeassistant.config_entries import SOURCE_USER, ConfigEntryState, ConfigSubentryData
from homeassistant.const import CONF_HOST, CONF_PORT
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import CONF_VENDOR, DOMAIN, SUBENTRY_POINT
from custom_components.plc_bridge.plc import BrowseItem, ConnectionConfig, PlcConnectionError
from custom_components.plc_bridge.point_form import browse_values
from tests.flow_fixtures import FAKE_VENDOR, FakeClient, error_message, suggested, translated

POINTS = ("config_subentries", SUBENTRY_POINT)
TEMPERATURE = BrowseItem(
    address="Main.temp",
    data_type="REAL",
    name="Temperature",
    unit="°C",
    minimum=0,
    maximum=100,
    read_only=True,
)
PUMP = BrowseItem(address="Main.pump", data_type="BOOL")
DONE = BrowseItem(address="Main.done", data_type="BOOL", name="Done")


@pytest.fixture
def fake_entry(hass: HomeAssistant, fake_vendor: type[FakeClient]) -> MockConfigEntry:
    """A loaded entry of the fake vendor with one point (Main.done) configured."""
    entry = MockConfigEntry(
        domain=DOMAIN,
        data={CONF_VENDOR: FAKE_VENDOR, CONF_HOST: "plc", CONF_PORT: 8080},
        unique_id="FAKE-1",
        subentries_data=[
            ConfigSubentryData(
                data={"platform": "binary_sensor", "address": "Main.done", "data_type": "BOOL"},
                subentry_type=SUBENTRY_POINT,
                title="Done",
                unique_id="Main.done|BOOL",
            )
        ],
    )
    entry.add_to_hass(hass)
    entry.mock_state(hass, ConfigEntryState.LOADED)
    entry.runtime_data = SimpleNamespace(client=FakeClient(ConnectionConfig(host="plc", port=1)))
    fake_vendor.items = [TEMPERATURE, PUMP, DONE]
    return entry


async def start(hass: HomeAssistant, entry: MockConfigEntry) -> Any:
    """Start adding a point."""
    result = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_POINT), context={"source": SOURCE_USER}
    )
    return translated(result, *POINTS)


async def choose(hass: HomeAssistant, result: Any, values: dict[str, Any]) -> Any:
    """Submit a step and check the answer is translated."""
    return translated(
        await hass.config_entries.subentries.async_configure(result["flow_id"], values), *POINTS
    )


async def test_browse_fills_in_the_point(hass: HomeAssistant, fake_entry: MockConfigEntry) -> None:
    """The variables not configured yet are offered; the chosen one fills in the form."""
    result = await start(hass, fake_entry)
    assert result["step_id"] == "browse"
    assert result["description_placeholders"] == {"count": "2"}
    options = result["data_schema"].schema["variable"].config["options"]
    assert options == [
        {"value": "manual", "label": "manual"},
        {"value": "0", "label": "Temperature – Main.temp (REAL)"},
        {"value": "1", "label": "Main.pump (BOOL)"},
    ]
    result = await choose(hass, result, {"variable": "0"})
    assert result["step_id"] == "user"
    expected = {
        "name": "Temperature",
        "address": "Main.temp",
        "data_type": "REAL",
        "unit_of_measurement": "°C",
        "min": 0,
        "max": 100,
        "read_only": True,
        "platform": "sensor",
    }
    assert {key: suggested(result, key) for key in expected} == expected
    result = await choose(hass, result, expected | {"scale": 1, "offset": 0})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["data"] == {
        "platform": "sensor",
        "address": "Main.temp",
        "data_type": "REAL",
        "unit_of_measurement": "°C",
        "min": 0.0,
        "max": 100.0,
        "scale": 1.0,
        "offset": 0.0,
        "read_only": True,
    }


async def test_enter_by_hand(hass: HomeAssistant, fake_entry: MockConfigEntry) -> None:
    """ "Enter an address by hand" leads to an empty point form."""
    result = await choose(hass, await start(hass, fake_entry), {"variable": "manual"})
    assert result["step_id"] == "user"
    assert suggested(result, "address") is None
    values = {"name": "X", "platform": "switch", "address": "x y", "data_type": "BOOL"}
    result = await choose(hass, result, values | {"scale": 1, "offset": 0, "read_only": False})
    assert error_message(result, "address", *POINTS) == (
        "Invalid address: 'x y' is not a variable name"
    )


async def test_browse_failure_falls_back_to_typing(
    hass: HomeAssistant, fake_entry: MockConfigEntry, fake_vendor: type[FakeClient]
) -> None:
    """A PLC that cannot list its variables: the form says so, typing still works."""
    fake_vendor.browse_error = PlcConnectionError("gone")
    result = await start(hass, fake_entry)
    assert result["step_id"] == "user"
    assert result["errors"] == {"base": "browse_failed"}
    assert error_message(result, "base", *POINTS) == (
        "The PLC did not list its variables (gone). Enter the address by hand."
    )


async def test_browse_needs_a_loaded_entry(
    hass: HomeAssistant, fake_entry: MockConfigEntry
) -> None:
    """Without a connection there is nothing to browse."""
    fake_entry.mock_state(hass, ConfigEntryState.NOT_LOADED)
    result = await start(hass, fake_entry)
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "entry_not_loaded"


@pytest.mark.parametrize(
    ("item", "platform"),
    [
        (BrowseItem(address="a", data_type="BOOL"), "switch"),
        (BrowseItem(address="a", data_type="BOOL", read_only=True), "binary_sensor"),
        (BrowseItem(address="a", data_type="INT"), "number"),
        (BrowseItem(address="a", data_type="REAL", read_only=True), "sensor"),
        (BrowseItem(address="a", data_type="DT"), "datetime"),
        (BrowseItem(address="a", data_type="STRING"), "text"),
        (BrowseItem(address="a", data_type="STRING", read_only=True), "sensor"),
        (BrowseItem(address="a", data_type="TIME"), "sensor"),
        (BrowseItem(address="1 a", data_type="BOOL"), "sensor"),
        (BrowseItem(address="a", data_type="BOOL", platform="binary_sensor"), "binary_sensor"),
    ],
)
def test_suggested_platform(item: BrowseItem, platform: str) -> None:
    """Writable variables get a control, read-only ones a sensor; the PLC's word wins."""
    assert browse_values(FakeClient, item)["platform"] == platform
