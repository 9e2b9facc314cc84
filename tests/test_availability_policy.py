"""The availability policy of each entity: follow the PLC, keep the last value, follow data-valid.

With the PLC away (the simulator stopped) and with a machine's data-valid address saying "not
valid", on the S7-200 SMART simulator under HA's time travel; then every door that stores the
policy (point form, composite form, table, pasted file) refusing an unknown one and `data_valid`
on a machine without the address.
"""

from __future__ import annotations

from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.const import STATE_OFF, STATE_ON, STATE_UNAVAILABLE
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import InvalidData, section
from homeassistant.util import dt as dt_util
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import DOMAIN
from custom_components.plc_bridge.model.availability import (
    CONF_AVAILABILITY_ADDRESS,
    CONF_AVAILABILITY_DATA_TYPE,
    check_policy,
)
from custom_components.plc_bridge.model.config_file import dump_config
from custom_components.plc_bridge.model.point_table import export_points, parse_points
from simulators.s7_smart import S7SmartSimulator
from tests.entries import add_entry, device, make_entry, point, poll, sim_data
from tests.flows.forms import entity_page, on_page, page_shown, step, strings_at
from tests.flows.test_command_layouts import SMART, key_only, machines
from tests.test_config_file import CONFIG, paste

pytestmark = pytest.mark.no_pacing

KEEP = {"availability": "keep"}
BOILER = [
    point("temperature", "Temperature", "sensor", "VW4", "signed"),
    point("flow", "Flow", "sensor", "VW6", "signed", availability="plc"),
    point("level", "Level", "sensor", "VW8", "signed", **KEEP),
    point("p1", "Burner", "switch", "I0.3", "signed", role="state", read_only=True, **KEEP),
    point("p2", "Burner", "switch", "M1.0", "signed", role="command", **KEEP),
]
"""A machine with a data-valid address (M0.0): its default, plc, keep (a point and an entity)."""
PUMP = [
    point("speed", "Speed", "sensor", "VW10", "signed"),
    point("hours", "Hours", "sensor", "VW12", "signed", **KEEP),
]
"""A machine without one: its default (plc) and keep."""
SHOWN = {
    "sensor.boiler_temperature": "temperature",
    "sensor.boiler_flow": "flow",
    "sensor.boiler_level": "level",
    "switch.boiler_burner": "burner",
    "sensor.pump_speed": "speed",
    "sensor.pump_hours": "hours",
}


def plant(hass: HomeAssistant, sim: S7SmartSimulator) -> MockConfigEntry:
    """Add an entry with the Boiler (data-valid address M0.0) and the Pump (none)."""
    boiler = device(BOILER, subentry_id="boiler", title="Boiler")
    boiler["data"] = {
        **boiler["data"],
        CONF_AVAILABILITY_ADDRESS: "M0.0",
        CONF_AVAILABILITY_DATA_TYPE: "signed",
    }
    return add_entry(
        hass,
        title="S7-200 SMART",
        entry_id="01JPLCBR1DGE0000000000P0LY",
        unique_id="plc-bridge-policy",
        data=sim_data(sim),
        subentries=[boiler, device(PUMP, subentry_id="pump", title="Pump")],
    )


def hold(sim: S7SmartSimulator, base: int) -> None:
    """Have the PLC hold its data valid, the burner on and every word `base` plus its index."""
    sim.set("M0.0", 1)
    sim.set("I0.3", True)
    for index, address in enumerate(("VW4", "VW6", "VW8", "VW10", "VW12")):
        sim.set(address, base + index)


def states(hass: HomeAssistant) -> dict[str, str]:
    """Return what each entity of SHOWN shows, by its short name."""
    found = {name: hass.states.get(entity_id) for entity_id, name in SHOWN.items()}
    return {name: state.state for name, state in found.items() if state is not None}


def last_read(hass: HomeAssistant) -> dict[str, Any]:
    """Return the `last_read` attribute of each entity of SHOWN that has one."""
    found = {name: hass.states.get(entity_id) for entity_id, name in SHOWN.items()}
    return {
        name: state.attributes["last_read"]
        for name, state in found.items()
        if state is not None and "last_read" in state.attributes
    }


async def test_each_policy_with_the_plc_away(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, freezer: FrozenDateTimeFactory
) -> None:
    """PLC away: plc and data_valid unavailable, keep shows its last value and when it was read."""
    hold(s7_smart_ha_sim, 10)
    entry = plant(hass, s7_smart_ha_sim)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    await poll(hass, freezer)
    read_at = dt_util.utcnow().isoformat()
    assert states(hass) == {
        "temperature": "10",
        "flow": "11",
        "level": "12",
        "burner": STATE_ON,
        "speed": "13",
        "hours": "14",
    }
    assert last_read(hass) == {}

    await s7_smart_ha_sim.stop()
    await poll(hass, freezer, 2)
    assert states(hass) == {
        "temperature": STATE_UNAVAILABLE,
        "flow": STATE_UNAVAILABLE,
        "level": "12",
        "burner": STATE_ON,
        "speed": STATE_UNAVAILABLE,
        "hours": "14",
    }
    assert last_read(hass) == {"level": read_at, "burner": read_at, "hours": read_at}

    hold(s7_smart_ha_sim, 20)
    s7_smart_ha_sim.set("I0.3", False)
    await s7_smart_ha_sim.start(s7_smart_ha_sim.host, s7_smart_ha_sim.port)
    await poll(hass, freezer)
    assert states(hass) == {
        "temperature": "20",
        "flow": "21",
        "level": "22",
        "burner": STATE_OFF,
        "speed": "23",
        "hours": "24",
    }
    assert last_read(hass) == {}


async def test_each_policy_with_data_not_valid(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, freezer: FrozenDateTimeFactory
) -> None:
    """Data-valid address says not valid: only its followers (the default there) unavailable."""
    hold(s7_smart_ha_sim, 10)
    entry = plant(hass, s7_smart_ha_sim)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    s7_smart_ha_sim.set("M0.0", 0)
    s7_smart_ha_sim.set("VW6", 31)
    await poll(hass, freezer, 2)
    assert states(hass) == {
        "temperature": STATE_UNAVAILABLE,
        "flow": "31",
        "level": "12",
        "burner": STATE_ON,
        "speed": "13",
        "hours": "14",
    }
    assert last_read(hass) == {}  # the PLC answers: nothing is kept


@pytest.mark.parametrize(
    ("given", "data_valid", "stored", "error"),
    [
        ("", False, {}, ""),
        ("plc", False, {}, ""),
        ("keep", False, {"availability": "keep"}, ""),
        ("data_valid", False, {}, "availability_policy_no_address"),
        ("sometimes", False, {}, "invalid_availability_policy"),
        ("plc", True, {"availability": "plc"}, ""),
        ("data_valid", True, {}, ""),
        ("sometimes", True, {}, "invalid_availability_policy"),
    ],
)
def test_one_check(given: str, data_valid: bool, stored: dict[str, str], error: str) -> None:
    """The one check: the default stores nothing; unknown and data_valid without address refused."""
    assert check_policy({"availability": given}, data_valid=data_valid) == (stored, error)


def test_table_column() -> None:
    """The table's `availability` column: checked per line as the forms check it, exported."""
    head = "name,address,platform,availability\n"
    rows = {
        "Level,VW10,sensor,keep\n": ([], [{"availability": "keep"}]),
        "Level,VW10,sensor,Keep\n": ([], [{"availability": "keep"}]),
        "Level,VW10,sensor,\n": ([], [{}]),
        "Level,VW10,sensor,sometimes\n": ([(2, "invalid_availability_policy")], []),
        "Level,VW10,sensor,data_valid\n": ([(2, "availability_policy_no_address")], []),
    }
    for lines, (errors, policies) in rows.items():
        points, found = parse_points(SMART, head + lines, describe=key_only)
        assert found == errors, lines
        assert [{k: v for k, v in p.items() if k == "availability"} for p in points] == policies
    points, found = parse_points(SMART, head + "Level,VW10,sensor,data_valid\n", data_valid=True)
    assert (found, [p.get("availability") for p in points]) == ([], [None])
    points, _ = parse_points(SMART, head + "Level,VW10,sensor,keep\n")
    table = export_points(points)
    assert "availability" in table.splitlines()[0].split(",")
    assert parse_points(SMART, table)[0] == points


@pytest.fixture
def smart_entry(hass: HomeAssistant, flow_sim: S7SmartSimulator) -> MockConfigEntry:
    """An S7-200 SMART entry without machines (not set up)."""
    entry = MockConfigEntry(domain=DOMAIN, data=sim_data(flow_sim), version=2)
    entry.add_to_hass(hass)
    return entry


async def machine_menu(
    hass: HomeAssistant, entry: MockConfigEntry, *, data_valid: bool
) -> dict[str, Any]:
    """Open a new machine, with a data-valid address (M0.0) or without, and return its menu."""
    result = await hass.config_entries.subentries.async_init(
        (entry.entry_id, "device"), context={"source": "user"}
    )
    given: dict[str, Any] = {"name": "Garage"}
    if data_valid:
        given |= {CONF_AVAILABILITY_ADDRESS: "M0.0", CONF_AVAILABILITY_DATA_TYPE: "signed"}
    result = await step(hass, result, given)
    assert result["step_id"] == "menu"
    return dict(result)


def offered(result: Any) -> list[str]:
    """Return the options of a form's availability field."""
    fields = dict(result["data_schema"].schema)
    for shown in list(fields.values()):
        if isinstance(shown, section):  # the entity page's folded options
            fields |= shown.schema.schema
    for marker, selector in fields.items():
        if str(marker) == "availability":
            return list(selector.config["options"])
    raise AssertionError("no availability field")


@pytest.mark.parametrize("data_valid", [False, True])
async def test_point_form(
    hass: HomeAssistant, smart_entry: MockConfigEntry, data_valid: bool
) -> None:
    """The point form offers data_valid only where the machine has the address; refuses others."""
    result = await step(
        hass,
        await machine_menu(hass, smart_entry, data_valid=data_valid),
        {"next_step_id": "point"},
    )
    base = {"name": "Level", "platform": "sensor", "address": "VW10", "data_type": "signed"}
    result = await step(hass, result, base)
    assert result["step_id"] == "details"
    wanted = ["plc", "keep", "data_valid"] if data_valid else ["plc", "keep"]
    assert offered(result) == wanted
    if not data_valid:
        for refused in ("data_valid", "sometimes"):  # not an option: the form refuses it
            with pytest.raises(InvalidData, match="availability"):
                await step(hass, result, {"availability": refused})
    result = await step(hass, result, {"availability": "keep"})
    assert result["step_id"] == "menu"
    await step(hass, result, {"next_step_id": "save"})
    assert [data.get("availability") for data in machines(smart_entry)] == ["keep"]


async def test_composite_form_stores_it_on_every_part(
    hass: HomeAssistant, smart_entry: MockConfigEntry
) -> None:
    """An entity of several points: one field on its page, stored on every part."""
    menu = await machine_menu(hass, smart_entry, data_valid=False)
    result = await entity_page(hass, menu, "switch")
    assert offered(result) == ["plc", "keep"]
    values = {"name": "Pump", "availability": "keep", "state": "I0.1", "command": "Q0.4"}
    result = await step(hass, result, on_page("switch", values))
    await step(hass, result, {"next_step_id": "save"})
    assert [data.get("availability") for data in machines(smart_entry)] == ["keep", "keep"]


@pytest.mark.parametrize("policy", ["sometimes", "data_valid"])
async def test_pasted_file_refuses_a_bad_policy(
    hass: HomeAssistant, flow_sim: S7SmartSimulator, policy: str
) -> None:
    """A pasted file with an unknown policy, or data_valid on a machine without it, adds no PLC."""
    entry = make_entry(
        hass, flow_sim, [point("p", "Level", "sensor", "VW10", "signed", availability=policy)]
    )
    text = dump_config(entry)
    assert await hass.config_entries.async_remove(entry.entry_id)
    result = await paste(hass, text)
    assert result["errors"] == {"configuration": "config_availability_policy"}
    assert "Level" in strings_at(*CONFIG, "error", "config_availability_policy").format(
        **result["description_placeholders"]
    )
    assert hass.config_entries.async_entries(DOMAIN) == []


async def test_pasted_file_keeps_a_good_policy(
    hass: HomeAssistant, flow_sim: S7SmartSimulator
) -> None:
    """A pasted file with a kept point passes the check."""
    entry = make_entry(hass, flow_sim, [point("p", "Level", "sensor", "VW10", "signed", **KEEP)])
    text = dump_config(entry)
    assert "availability: keep" in text
    assert await hass.config_entries.async_remove(entry.entry_id)
    result = await paste(hass, text)
    assert result.get("errors") in (None, {})


def test_parts_of_one_entity_agree() -> None:
    """Rows of one entity giving different availabilities are refused on its first line."""
    head = "name,address,platform,role,read_only,availability\n"
    rows = {
        "Pump,I0.1,switch,state,true,keep\nPump,Q0.4,switch,command,false,keep\n": [],
        "Pump,I0.1,switch,state,true,keep\nPump,Q0.4,switch,command,false,\n": [
            (2, "availability_differs")
        ],
    }
    for lines, expected in rows.items():
        assert parse_points(SMART, head + lines, describe=key_only)[1] == expected, lines


async def test_pasted_file_refuses_parts_that_differ(
    hass: HomeAssistant, flow_sim: S7SmartSimulator
) -> None:
    """A pasted file whose entity's parts give different availabilities adds no PLC."""
    points = [
        point("s", "Pump", "switch", "I0.1", "signed", role="state", read_only=True, **KEEP),
        point("c", "Pump", "switch", "Q0.4", "signed", role="command"),
    ]
    entry = make_entry(hass, flow_sim, points)
    text = dump_config(entry)
    assert await hass.config_entries.async_remove(entry.entry_id)
    result = await paste(hass, text)
    assert result["errors"] == {"configuration": "config_availability_policy"}
    assert hass.config_entries.async_entries(DOMAIN) == []


async def test_composite_edit_changes_every_part(
    hass: HomeAssistant, smart_entry: MockConfigEntry
) -> None:
    """Editing one part's address form sets the availability of the whole entity."""
    menu = await machine_menu(hass, smart_entry, data_valid=False)
    result = await entity_page(hass, menu, "switch")
    values = {"name": "Pump", "state": "I0.1", "command": "Q0.4"}
    result = await step(hass, result, on_page("switch", values))
    result = await step(hass, result, {"next_step_id": "edit"})
    (marker,) = result["data_schema"].schema
    first = result["data_schema"].schema[marker].config["options"][0]
    result = await step(hass, result, {"point": first["value"]})
    assert result["step_id"] == "composite_entity"
    assert offered(result) == ["plc", "keep"]
    page = page_shown(result)
    page["entity_options"]["availability"] = "keep"
    result = await step(hass, result, page)
    await step(hass, result, {"next_step_id": "save"})
    assert [data.get("availability") for data in machines(smart_entry)] == ["keep", "keep"]
