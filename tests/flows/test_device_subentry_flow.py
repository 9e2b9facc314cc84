"""The device subentry flow: name and area, then a menu to add, pick, import, edit and remove."""

from __future__ import annotations

from typing import Any

from homeassistant.config_entries import SOURCE_USER
from homeassistant.const import CONF_HOST, CONF_PORT
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import area_registry as ar
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import CONF_POINTS, CONF_VENDOR, DOMAIN, SUBENTRY_DEVICE
from custom_components.plc_bridge.model.point_table import export_points
from simulators.s7_smart import S7SmartSimulator
from tests.entries import device, point, sim_data
from tests.flows.forms import error_message, translated

pytestmark = pytest.mark.no_pacing

DEVICE = ("config_subentries", SUBENTRY_DEVICE)
TEMPERATURE = {"name": "Tank", "platform": "sensor", "address": "vd100", "data_type": "float"}
CELSIUS = {"device_class": "temperature", "unit_of_measurement": "°C", "scale": 1.0}


@pytest.fixture
def smart_entry(hass: HomeAssistant, flow_sim: S7SmartSimulator) -> MockConfigEntry:
    """An S7-200 SMART entry (not set up) with one device holding VW10."""
    entry = MockConfigEntry(
        domain=DOMAIN,
        data=sim_data(flow_sim),
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


async def paste(hass: HomeAssistant, menu: Any, table: str) -> Any:
    """Import a pasted table from the menu."""
    result = await step(hass, menu, {"next_step_id": "import_points"})
    return await step(hass, result, {"table": table})


def saved(entry: MockConfigEntry, title: str) -> dict[str, dict[str, Any]]:
    """Return the points of the entry's one device with this title."""
    (subentry,) = [s for s in entry.subentries.values() if s.title == title]
    return dict(subentry.data[CONF_POINTS])


async def test_add_two_points_and_save(hass: HomeAssistant, smart_entry: MockConfigEntry) -> None:
    """Two points, one device subentry with its area; addresses normalized by the parser."""
    area = ar.async_get(hass).async_create("Boiler room")
    result = await hass.config_entries.subentries.async_init(
        (smart_entry.entry_id, SUBENTRY_DEVICE), context={"source": SOURCE_USER}
    )
    result = await step(hass, result, {"name": " "})
    assert result["errors"] == {"name": "device_name_required"}
    menu = await step(hass, result, {"name": "Heating", "area": area.id})
    assert "save" not in menu["menu_options"]  # a device needs a point
    menu = await add_point(hass, menu, TEMPERATURE, **CELSIUS, state_class="measurement")
    assert menu["type"] is FlowResultType.MENU
    switch = {"name": "Pump", "platform": "switch", "address": "Q0.0", "data_type": "signed"}
    menu = await add_point(hass, menu, switch)
    assert menu["description_placeholders"]["count"] == "2"
    result = await step(hass, menu, {"next_step_id": "save"})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    (new,) = [s for s in smart_entry.subentries.values() if s.title == "Heating"]
    assert new.data["area"] == area.id
    points = sorted(new.data[CONF_POINTS].values(), key=lambda data: data["name"])
    assert [(p["name"], p["address"], p["platform"]) for p in points] == [
        ("Pump", "Q0.0", "switch"),
        ("Tank", "VD100", "sensor"),
    ]
    assert points[1]["device_class"] == "temperature"
    assert points[1]["unit_of_measurement"] == "°C"
    assert len({*new.data[CONF_POINTS]}) == 2


@pytest.mark.parametrize(
    ("base", "field", "key", "text"),
    [
        ({**TEMPERATURE, "address": "VX7"}, "address", "invalid_address", "Invalid address"),
        (
            {**TEMPERATURE, "platform": "switch"},
            "platform",
            "needs_bool",
            "VD100 as Floating point (REAL) is not",  # the type's name, not its key
        ),
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


def field(result: Any, name: str) -> Any:
    """Return the selector of a form's field."""
    return next(value for key, value in result["data_schema"].schema.items() if str(key) == name)


async def test_details_fit_the_point(hass: HomeAssistant, smart_entry: MockConfigEntry) -> None:
    """A numeric sensor is offered no timestamp; units and state classes must fit the class."""
    menu = await new_device(hass, smart_entry)
    result = await step(hass, menu, {"next_step_id": "point"})
    result = await step(hass, result, TEMPERATURE)
    classes = field(result, "device_class").config
    assert "temperature" in classes["options"]
    assert "timestamp" not in classes["options"]
    assert classes["translation_key"] == "sensor_device_class"
    result = await step(hass, result, {**CELSIUS, "unit_of_measurement": "bar", "offset": 0.0})
    assert result["errors"] == {"unit_of_measurement": "unit_not_valid"}
    assert error_message(result, "unit_of_measurement", *DEVICE).endswith("K, °C, °F.")
    assert set(field(result, "unit_of_measurement").config["options"]) == {"K", "°C", "°F"}
    result = await step(hass, result, {**CELSIUS, "state_class": "total_increasing"})
    assert result["errors"] == {"state_class": "state_class_not_valid"}
    result = await step(hass, result, {"device_class": "temperature", "scale": 1.0})
    assert result["errors"] == {"unit_of_measurement": "unit_required"}
    menu = await step(hass, result, {**CELSIUS, "state_class": "measurement"})
    assert menu["type"] is FlowResultType.MENU


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
    base = {"name": "Tank level", "platform": "sensor", "address": "VW10", "data_type": "signed"}
    result = await step(hass, result, base)
    result = await step(hass, result, {"scale": 0.1, "offset": 0.0, "read_only": True})
    menu = await add_point(hass, result, TEMPERATURE, scale=1.0, offset=0.0)
    result = await step(hass, menu, {"next_step_id": "remove"})
    result = await step(hass, result, {"point": []})
    result = await step(hass, result, {"next_step_id": "device"})
    result = await step(hass, result, {"name": "Tank"})
    result = await step(hass, result, {"next_step_id": "save"})
    assert result["reason"] == "reconfigure_successful"
    assert smart_entry.subentries[subentry.subentry_id].title == "Tank"
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


async def test_a_new_entity_type_drops_the_old_class(
    hass: HomeAssistant, smart_entry: MockConfigEntry
) -> None:
    """A bit shown as a sensor (1 or 0), edited into a binary sensor: no sensor class suggested."""
    bit = {"name": "Burner", "platform": "sensor", "address": "I0.0", "data_type": "signed"}
    menu = await add_point(
        hass, await new_device(hass, smart_entry), bit, device_class="power_factor"
    )
    result = await step(hass, menu, {"next_step_id": "edit"})
    (option,) = field(result, "point").config["options"]
    result = await step(hass, result, {"point": option["value"]})
    result = await step(hass, result, {**bit, "platform": "number"})
    assert result["errors"] == {"platform": "needs_number"}
    result = await step(hass, result, {**bit, "platform": "binary_sensor"})
    assert field(result, "device_class").config["translation_key"] == "binary_sensor_device_class"
    marker = next(key for key in result["data_schema"].schema if str(key) == "device_class")
    assert (marker.description or {}).get("suggested_value") is None


async def test_import_500_lines(hass: HomeAssistant, smart_entry: MockConfigEntry) -> None:
    """500 pasted lines become 500 points in one step; the menu lists the first 5, by name."""
    lines = ["name\taddress\tdata_type"] + [
        f"Word {i}\tVW{100 + 2 * i}\tsigned" for i in range(500)
    ]
    menu = await new_device(hass, smart_entry, "Line 1")
    result = await paste(hass, menu, "\n".join(lines))
    assert result["type"] is FlowResultType.MENU
    assert result["description_placeholders"]["count"] == "500"
    assert result["description_placeholders"]["points"].splitlines() == [
        *(f"- Word {i} (sensor): VW{100 + 2 * i} (Signed integer)" for i in range(5)),
        "- … (+495)",
    ]
    result = await step(hass, result, {"next_step_id": "save"})
    assert len(saved(smart_entry, "Line 1")) == 500


async def test_import_names_bad_lines(hass: HomeAssistant, smart_entry: MockConfigEntry) -> None:
    """Bad lines are named by number, in the form's own words; nothing joins the device."""
    table = "name,address,data_type\nGood,VW100,signed\nBad,VX100,signed\nTaken,VW10,signed"
    menu = await new_device(hass, smart_entry)
    result = await paste(hass, menu, table)
    assert result["errors"] == {"table": "import_failed"}
    listed = result["description_placeholders"]["errors"].splitlines()
    assert listed[0].startswith("- line 3: Invalid address: 'VX100' is not an S7-200 SMART")
    assert listed[1] == "- line 4: The PLC already has a point with this address and data type."
    result = await step(hass, result, {"table": "name,address\nGood,VW100"})
    assert result["errors"] == {"table": "import_types_assumed"}  # no type: shown, then taken
    result = await step(hass, result, {"table": "name,address\nGood,VW100"})
    assert result["description_placeholders"]["count"] == "1"


async def test_export_then_import(hass: HomeAssistant, smart_entry: MockConfigEntry) -> None:
    """A device's exported points, imported again, are the same points."""
    menu = await new_device(hass, smart_entry, "Source")
    table = (
        "name,address,data_type,platform,unit,device_class,state_class,scale,min,max,step\n"
        '"Tank, ""north""",VD100,float,sensor,°C,temperature,measurement,0.1,,,\n'
        "Setpoint,VW20,signed,number,,,,0.5,10,60,0.5\n"
        "Pump,Q0.0,signed,switch,,,,,,,\n"
    )
    await step(hass, await paste(hass, menu, table), {"next_step_id": "save"})
    before = saved(smart_entry, "Source")
    exported = export_points(before.values())
    (source,) = [s for s in smart_entry.subentries.values() if s.title == "Source"]
    result = await smart_entry.start_subentry_reconfigure_flow(hass, source.subentry_id)
    result = await step(hass, result, {"next_step_id": "remove"})
    result = await step(hass, result, {"point": list(before)})
    result = await paste(hass, result, exported)
    await step(hass, result, {"next_step_id": "save"})
    again = saved(smart_entry, "Source")
    assert sorted(again.values(), key=str) == sorted(before.values(), key=str)
    assert not set(again) & set(before)  # new ids: new entities


async def test_micro_win_smart_paste(hass: HomeAssistant, smart_entry: MockConfigEntry) -> None:
    """A STEP 7-Micro/WIN SMART symbol table becomes read-only points, assumed types shown first."""
    table = "Symbol\tAddress\tComment\nFlow\tVD100\tFlow rate REAL\nPump\tQ0.0\tMain pump\n"
    result = await paste(hass, await new_device(hass, smart_entry, "Pumps"), table)
    assert result["errors"] == {"table": "import_types_assumed"}
    assert result["description_placeholders"]["errors"].splitlines() == [
        "- line 2: VD100 (signed?): the table names no data type, this one is assumed."
    ]
    menu = await step(hass, result, {"table": table})
    await step(hass, menu, {"next_step_id": "save"})
    points = {data["name"]: data for data in saved(smart_entry, "Pumps").values()}
    assert (points["Flow"]["data_type"], points["Pump"]["platform"]) == ("signed", "binary_sensor")


async def test_tia_portal_paste(hass: HomeAssistant) -> None:
    """A TIA Portal tag table pasted into an S7 PLC's device."""
    entry = MockConfigEntry(
        domain=DOMAIN,
        data={CONF_VENDOR: "s7", CONF_HOST: "127.0.0.1", CONF_PORT: 102},
        version=2,
    )
    entry.add_to_hass(hass)
    table = (
        "Name\tPath\tData Type\tLogical Address\tComment\n"
        "Motor on\tDefault tag table\tBool\t%Q0.0\t\n"
        "Speed\tDefault tag table\tInt\t%MW20\tRPM\n"
    )
    menu = await paste(hass, await new_device(hass, entry, "Motor"), table)
    await step(hass, menu, {"next_step_id": "save"})
    points = sorted(saved(entry, "Motor").values(), key=lambda data: data["name"])
    assert [(p["address"], p["data_type"], p["platform"]) for p in points] == [
        ("Q0.0", "BOOL", "binary_sensor"),
        ("MW20", "INT", "sensor"),
    ]
