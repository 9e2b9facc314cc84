"""The device subentry flow: name and area, then a menu to add, pick, import, edit and remove."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

from homeassistant.config_entries import SOURCE_USER, ConfigEntryState
from homeassistant.const import CONF_HOST, CONF_PORT
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import CONF_POINTS, CONF_VENDOR, DOMAIN, SUBENTRY_DEVICE
from custom_components.plc_bridge.plc import BrowseItem, ConnectionConfig
from simulators.s7_smart import S7SmartSimulator

from .flow_fixtures import FAKE_VENDOR, FakeClient, error_message, smart_data, translated
from .ha_fixtures import device, point

DEVICE = ("config_subentries", SUBENTRY_DEVICE)
TEMPERATURE = {"name": "Tank", "platform": "sensor", "address": "vd100", "data_type": "float"}


@pytest.fixture
def smart_entry(hass: HomeAssistant, flow_sim: S7SmartSimulator) -> MockConfigEntry:
    """An S7-200 SMART entry (not set up) with one device holding VW10."""
    entry = MockConfigEntry(
        domain=DOMAIN,
        data=smart_data(flow_sim),
        version=2,
        subentries_data=[device([point("level", "Level", "sensor", "VW10", "signed")])],
    )
    entry.add_to_hass(hass)
    return entry


async def step(hass: HomeAssistant, result: Any, values: dict[str, Any] | None = None) -> Any:
    """Submit a form (or pick a menu option given as {"next_step_id": ...}); check its texts."""
    return translated(
        await hass.config_entries.subentries.async_configure(result["flow_id"], values or {}),
        *DEVICE,
    )


async def new_device(hass: HomeAssistant, entry: MockConfigEntry, name: str = "Boiler") -> Any:
    """Start a device flow and name the device; return the menu."""
    result = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_DEVICE), context={"source": SOURCE_USER}
    )
    assert result["step_id"] == "device"
    result = await step(hass, result, {"name": name})
    assert result["type"] is FlowResultType.MENU
    return result


async def add_point(hass: HomeAssistant, menu: Any, base: dict[str, Any], **details: Any) -> Any:
    """Add a point through the two point forms; return the result of the second."""
    result = await step(hass, menu, {"next_step_id": "point"})
    result = await step(hass, result, base)
    if result["step_id"] != "details":
        return result
    return await step(hass, result, {"read_only": False, **details})


async def test_add_two_points_and_save(hass: HomeAssistant, smart_entry: MockConfigEntry) -> None:
    """Two points, one device subentry; addresses normalized by the vendor's parser."""
    menu = await new_device(hass, smart_entry, "Heating")
    menu = await add_point(
        hass,
        menu,
        TEMPERATURE,
        unit_of_measurement="°C",
        device_class="temperature",
        state_class="measurement",
        scale=1.0,
        offset=0.0,
    )
    assert menu["type"] is FlowResultType.MENU
    switch = {"name": "Pump", "platform": "switch", "address": "Q0.0", "data_type": "signed"}
    menu = await add_point(hass, menu, switch)
    assert menu["description_placeholders"]["count"] == "2"
    result = await step(hass, menu, {"next_step_id": "save"})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    new = [s for s in smart_entry.subentries.values() if s.title == "Heating"]
    assert len(new) == 1
    points = sorted(new[0].data[CONF_POINTS].values(), key=lambda data: data["name"])
    assert [(p["name"], p["address"], p["platform"]) for p in points] == [
        ("Pump", "Q0.0", "switch"),
        ("Tank", "VD100", "sensor"),
    ]
    assert points[1]["device_class"] == "temperature"
    assert points[1]["unit_of_measurement"] == "°C"


@pytest.mark.parametrize(
    ("base", "field", "key", "text"),
    [
        ({**TEMPERATURE, "address": "VX7"}, "address", "invalid_address", "Invalid address"),
        ({**TEMPERATURE, "platform": "switch"}, "platform", "needs_bool", "VD100 as float"),
        (
            {**TEMPERATURE, "address": "VW10", "data_type": "signed"},
            "address",
            "already_configured",
            "already has a point",
        ),
    ],
)
async def test_point_refused(  # noqa: PLR0917
    hass: HomeAssistant,
    smart_entry: MockConfigEntry,
    base: dict[str, Any],
    field: str,
    key: str,
    text: str,
) -> None:
    """The first form names the field at fault with the parser's words; nothing is added."""
    menu = await new_device(hass, smart_entry)
    result = await add_point(hass, menu, base)
    assert result["errors"] == {field: key}
    assert text in error_message(result, field, *DEVICE)


async def test_details_fit_the_point(hass: HomeAssistant, smart_entry: MockConfigEntry) -> None:
    """A numeric sensor is offered no timestamp class; a unit the class cannot carry is refused."""
    menu = await new_device(hass, smart_entry)
    result = await step(hass, menu, {"next_step_id": "point"})
    result = await step(hass, result, TEMPERATURE)
    classes = next(
        marker for marker in result["data_schema"].schema if str(marker) == "device_class"
    )
    options = result["data_schema"].schema[classes].config["options"]
    assert "temperature" in options
    assert "timestamp" not in options
    assert result["data_schema"].schema[classes].config["translation_key"] == (
        "sensor_device_class"
    )
    result = await step(
        hass,
        result,
        {
            "device_class": "temperature",
            "unit_of_measurement": "bar",
            "scale": 1.0,
            "offset": 0.0,
            "read_only": True,
        },
    )
    assert result["errors"] == {"unit_of_measurement": "unit_not_valid"}
    result = await step(
        hass,
        result,
        {
            "device_class": "temperature",
            "state_class": "total_increasing",
            "unit_of_measurement": "°C",
            "scale": 1.0,
            "offset": 0.0,
            "read_only": True,
        },
    )
    assert result["errors"] == {"state_class": "state_class_not_valid"}


async def test_edit_and_remove_in_reconfigure(
    hass: HomeAssistant, smart_entry: MockConfigEntry
) -> None:
    """Reconfigure opens the menu: an edited point keeps its id, a removed one goes."""
    (subentry,) = smart_entry.subentries.values()
    result = await smart_entry.start_subentry_reconfigure_flow(hass, subentry.subentry_id)
    assert result["type"] is FlowResultType.MENU
    result = await step(hass, result, {"next_step_id": "edit"})
    result = await step(hass, result, {"point": "level"})
    assert result["step_id"] == "point"
    result = await step(
        hass,
        result,
        {"name": "Tank level", "platform": "sensor", "address": "VW10", "data_type": "signed"},
    )
    result = await step(hass, result, {"scale": 0.1, "offset": 0.0, "read_only": True})
    menu = await add_point(hass, result, TEMPERATURE, scale=1.0, offset=0.0)
    result = await step(hass, menu, {"next_step_id": "remove"})
    result = await step(hass, result, {"point": []})
    result = await step(hass, result, {"next_step_id": "save"})
    assert result["reason"] == "reconfigure_successful"
    points = smart_entry.subentries[subentry.subentry_id].data[CONF_POINTS]
    assert points["level"]["name"] == "Tank level"
    assert points["level"]["scale"] == 0.1
    assert len(points) == 2
    result = await smart_entry.start_subentry_reconfigure_flow(hass, subentry.subentry_id)
    result = await step(hass, result, {"next_step_id": "remove"})
    result = await step(hass, result, {"point": ["level"]})
    result = await step(hass, result, {"next_step_id": "save"})
    (left,) = smart_entry.subentries[subentry.subentry_id].data[CONF_POINTS].values()
    assert left["address"] == "VD100"


async def test_import_500_lines(hass: HomeAssistant, smart_entry: MockConfigEntry) -> None:
    """500 pasted lines become 500 points in one step."""
    lines = ["name\taddress\tdata_type"] + [
        f"Word {i}\tVW{100 + 2 * i}\tsigned" for i in range(500)
    ]
    menu = await new_device(hass, smart_entry, "Line 1")
    result = await step(hass, menu, {"next_step_id": "import_points"})
    result = await step(hass, result, {"table": "\n".join(lines)})
    assert result["type"] is FlowResultType.MENU
    assert result["description_placeholders"]["count"] == "500"
    result = await step(hass, result, {"next_step_id": "save"})
    (new,) = [s for s in smart_entry.subentries.values() if s.title == "Line 1"]
    assert len(new.data[CONF_POINTS]) == 500


async def test_import_names_bad_lines(hass: HomeAssistant, smart_entry: MockConfigEntry) -> None:
    """A bad address is named by its line number; nothing joins the device."""
    table = "name,address,data_type\nGood,VW100,signed\nBad,VX100,signed\nTaken,VW10,signed"
    menu = await new_device(hass, smart_entry)
    result = await step(hass, menu, {"next_step_id": "import_points"})
    result = await step(hass, result, {"table": table})
    assert result["errors"] == {"table": "import_failed"}
    listed = result["description_placeholders"]["errors"]
    assert "line 3: address: invalid_address" in listed
    assert "line 4: VW10 (signed) is already a point" in listed
    result = await step(hass, result, {"table": "name,address\nGood,VW100"})
    assert result["description_placeholders"]["count"] == "1"


ITEMS = [
    BrowseItem(address=f"Main.temp{i}", data_type="REAL", name=f"Temp {i}", unit="°C")
    for i in range(300)
] + [BrowseItem(address="Main.pump", data_type="BOOL", name="Pump")]


@pytest.fixture
def browse_entry(hass: HomeAssistant, fake_vendor: type[FakeClient]) -> MockConfigEntry:
    """A loaded entry of a vendor that lists 301 variables."""
    entry = MockConfigEntry(
        domain=DOMAIN,
        data={CONF_VENDOR: FAKE_VENDOR, CONF_HOST: "plc", CONF_PORT: 8080},
        version=2,
    )
    entry.add_to_hass(hass)
    entry.mock_state(hass, ConfigEntryState.LOADED)
    entry.runtime_data = SimpleNamespace(client=FakeClient(ConnectionConfig(host="plc", port=1)))
    fake_vendor.items = ITEMS
    return entry


async def test_pick_filtered_variables(hass: HomeAssistant, browse_entry: MockConfigEntry) -> None:
    """A filter narrows 301 variables; several picks at once become points."""
    menu = await new_device(hass, browse_entry)
    result = await step(hass, menu, {"next_step_id": "browse"})
    result = await step(hass, result, {})
    assert result["description_placeholders"] == {"count": "301", "shown": "200"}
    menu = await step(hass, result, {})  # nothing picked: back to the menu
    result = await step(hass, menu, {"next_step_id": "browse"})
    result = await step(hass, result, {"filter": "temp1"})
    assert result["step_id"] == "pick"
    assert result["description_placeholders"]["count"] == "111"  # temp1, temp10-19, temp100-199
    result = await step(hass, result, {"variables": ["0", "1"]})
    assert result["description_placeholders"]["count"] == "2"
    result = await step(hass, result, {"next_step_id": "browse"})
    result = await step(hass, result, {"filter": "PUMP"})
    result = await step(hass, result, {"variables": ["0"]})
    result = await step(hass, result, {"next_step_id": "save"})
    (new,) = browse_entry.subentries.values()
    points = {data["address"]: data for data in new.data[CONF_POINTS].values()}
    assert set(points) == {"Main.temp1", "Main.temp10", "Main.pump"}
    assert points["Main.temp1"]["unit_of_measurement"] == "°C"
    assert points["Main.pump"]["platform"] == "switch"


async def test_browse_needs_a_loaded_entry(
    hass: HomeAssistant, smart_entry: MockConfigEntry, fake_vendor: type[FakeClient]
) -> None:
    """A vendor that cannot list variables has no pick option in its menu."""
    menu = await new_device(hass, smart_entry)
    assert "browse" not in menu["menu_options"]
