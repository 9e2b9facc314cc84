"""An entity of several addresses on one page, built from its kind's description.

From a machine's menu: the kinds' menu, then the entity's page (name, the kind's own device
class and time, a section per function, polling folded away). Each kind is built through its
page; errors land on the field or, for a field inside a section, on its section (Home
Assistant's frontend shows them there). A count of the pages and typed fields holds each kind
at the limits issue 25 set: a cover in 3 pages and 6 typed fields, a climate in 3 and 8, a
select, a button and an alarm word in 2 pages after the menu.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from homeassistant.config_entries import SOURCE_USER
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType, section
from homeassistant.helpers.selector import NumberSelector, TextSelector
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import CONF_POINTS, SUBENTRY_DEVICE
from custom_components.plc_bridge.flows.composite_flow import filled
from custom_components.plc_bridge.model.kinds import COMPOSITE_PLATFORMS, KINDS
from tests.flows.forms import MACHINE, page_shown, step, strings_at

pytestmark = pytest.mark.no_pacing

TYPED = (TextSelector, NumberSelector)
"""Fields a user types into; selects, switches and menus are clicks."""


@dataclass
class Walk:
    """A machine flow walked as a user would: the pages seen and the fields typed."""

    hass: HomeAssistant
    result: Any
    pages: int = 1  # the machine's menu, where the walk starts
    typed: int = 0
    seen: list[str] = field(default_factory=list)

    async def pick(self, option: str) -> Any:
        """Choose a menu option; count the page it opens."""
        return await self._submit({"next_step_id": option})

    async def fill(self, values: dict[str, Any]) -> Any:
        """Submit the form shown with these values; count those typed, and the next page."""
        self.typed += typed_fields(self.result, values)
        return await self._submit(values)

    async def _submit(self, values: dict[str, Any]) -> Any:
        """Submit and count the page shown next, unless it is the menu the walk began at."""
        self.result = await step(self.hass, self.result, values)
        self.seen.append(str(self.result.get("step_id")))
        if self.result.get("step_id") != "menu":
            self.pages += 1
        return self.result


def typed_fields(result: Any, values: dict[str, Any]) -> int:
    """Return how many of the values given fill a field the user types into."""
    count = 0
    for marker, shown in result["data_schema"].schema.items():
        given, fields = values, {marker: shown}
        if isinstance(shown, section):
            given, fields = values.get(str(marker), {}), shown.schema.schema
        for inner, selector in fields.items():
            value = given.get(str(inner))
            count += isinstance(selector, TYPED) and value not in (None, "")
    return count


async def machine_menu(hass: HomeAssistant, entry: MockConfigEntry) -> Walk:
    """Open a new machine and return the walk from its menu."""
    result = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_DEVICE), context={"source": SOURCE_USER}
    )
    result = await step(hass, result, {"name": "Garage"})
    assert result["type"] is FlowResultType.MENU
    return Walk(hass, result)


async def entity_page(hass: HomeAssistant, entry: MockConfigEntry, platform: str) -> Walk:
    """Walk from the machine's menu to the page of a new entity of this kind."""
    walk = await machine_menu(hass, entry)
    kinds = await walk.pick("composite")
    assert kinds["type"] is FlowResultType.MENU
    assert kinds["menu_options"] == [f"entity_{kind}" for kind in COMPOSITE_PLATFORMS]
    page = await walk.pick(f"entity_{platform}")
    assert page["step_id"] == "composite_entity"
    return walk


def sections_of(result: Any) -> dict[str, section]:
    """Return the page's sections by name."""
    return {
        str(marker): shown
        for marker, shown in result["data_schema"].schema.items()
        if isinstance(shown, section)
    }


def inner_fields(result: Any, name: str) -> set[str]:
    """Return the fields of one section of the page."""
    return {str(marker) for marker in sections_of(result)[name].schema.schema}


def problem(result: Any, name: str) -> str:
    """Return the error key behind a section's message; check the message names its role."""
    assert result["errors"][name] == f"in_{name}"
    placeholders = result["description_placeholders"]
    message = placeholders[f"{name}_problem"]
    errors = strings_at(*MACHINE, "error")
    found = [key for key, text in errors.items() if filled(text, placeholders) == message]
    assert found, message
    return found[0]


def stored(entry: MockConfigEntry) -> dict[str, dict[str, Any]]:
    """Return the saved machine's parts by role."""
    (device,) = entry.subentries.values()
    return {str(data.get("role")): dict(data) for data in device.data[CONF_POINTS].values()}


COVER = {
    "name": "Shutter",
    "device_class": "shutter",
    "commands": {"open": "Q0.4", "close": "Q0.5"},
    "limits": {"open_limit": "I0.1", "closed_limit": "I0.2", "closed_limit_invert": True},
}
"""The cover of the issue: open and close commands, two limit switches, a new machine."""
CLIMATE = {
    "name": "Boiler",
    "temperatures": {
        "current_temperature": "VD100",
        "current_temperature_data_type": "float",
        "target_temperature": "VD104",
        "target_temperature_data_type": "float",
        "unit_of_measurement": "°C",
        "min": 5,
        "max": 30,
        "step": 0.5,
    },
    "modes": {"hvac_mode": "VW108", "hvac_mode_value_map": "0=off;1=heat"},
}
"""The climate of the issue: current and target temperature, 5-30 °C step 0.5, a mode map."""


async def test_cover_in_three_pages(hass: HomeAssistant, flow_entry: MockConfigEntry) -> None:
    """Menu, kind, page: 3 pages and 5 typed fields; every part stored as its role needs."""
    walk = await entity_page(hass, flow_entry, "cover")
    page = walk.result
    assert set(sections_of(page)) == {
        "commands",
        "position",
        "limits",
        "tilt",
        "entity_options",
    }
    folded = {name for name, shown in sections_of(page).items() if shown.options["collapsed"]}
    assert folded == {"position", "tilt", "entity_options"}
    assert "read_only" not in str(page["data_schema"].schema)  # a command is never read only
    assert "pulse" in inner_fields(page, "commands")
    assert "closed_limit_invert" in inner_fields(page, "limits")
    menu = await walk.fill(COVER)
    assert menu["step_id"] == "menu", menu.get("errors")
    assert (walk.pages, walk.typed) == (3, 5)
    assert walk.pages <= 3
    assert walk.typed <= 6
    await step(hass, menu, {"next_step_id": "save"})
    parts = stored(flow_entry)
    assert set(parts) == {"open", "close", "open_limit", "closed_limit"}
    assert {data["name"] for data in parts.values()} == {"Shutter"}
    assert {data["device_class"] for data in parts.values()} == {"shutter"}
    assert parts["open"]["read_only"] is False
    assert parts["open_limit"]["read_only"] is True
    assert parts["closed_limit"].get("invert") is True
    assert "invert" not in parts["open_limit"]
    assert parts["open"]["data_type"] == parts["open_limit"]["data_type"]  # a bit, first fitting


async def test_climate_in_three_pages(hass: HomeAssistant, flow_entry: MockConfigEntry) -> None:
    """3 pages and 8 typed fields; the unit and scale asked once serve both temperatures."""
    walk = await entity_page(hass, flow_entry, "climate")
    assert inner_fields(walk.result, "temperatures") >= {"unit_of_measurement", "scale", "min"}
    assert "device_class" not in str(list(walk.result["data_schema"].schema))
    menu = await walk.fill(CLIMATE)
    assert menu["step_id"] == "menu", menu.get("errors")
    assert (walk.pages, walk.typed) == (3, 8)
    await step(hass, menu, {"next_step_id": "save"})
    parts = stored(flow_entry)
    assert set(parts) == {"current_temperature", "target_temperature", "hvac_mode"}
    current, target = parts["current_temperature"], parts["target_temperature"]
    assert current["unit_of_measurement"] == target["unit_of_measurement"] == "°C"
    assert (target["min"], target["max"], target["step"]) == (5.0, 30.0, 0.5)
    assert "min" not in current
    assert target["read_only"] is False
    assert current["read_only"] is True
    assert parts["hvac_mode"]["value_map"] == "0=off;1=heat"


@pytest.mark.parametrize(
    ("platform", "values", "typed"),
    [
        ("select", {"value_map": "0=Off;1=Auto"}, 3),
        ("button", {"pulse": 0.5}, 3),
        ("event", {"bits": "0=Overheat;3=Low water"}, 3),
    ],
)
async def test_one_address_kinds_in_two_pages(
    hass: HomeAssistant,
    flow_entry: MockConfigEntry,
    platform: str,
    values: dict[str, Any],
    typed: int,
) -> None:
    """A select, a pulse button and an alarm word: 2 pages after the machine's menu."""
    walk = await machine_menu(hass, flow_entry)
    await walk.pick("point")
    address = "Q0.6" if platform == "button" else "VW120"
    where = {"name": "Thing", "platform": platform, "address": address, "data_type": "signed"}
    details = await walk.fill(where)
    assert details["step_id"] == "details"
    menu = await walk.fill({**values, "read_only": platform != "event"} | _writable(platform))
    assert menu["step_id"] == "menu", menu.get("errors")
    assert walk.pages - 1 <= 2
    assert walk.typed == typed


def _writable(platform: str) -> dict[str, Any]:
    """Return the read-only switch a written kind must leave off."""
    return {"read_only": False} if platform in ("select", "button") else {}


@pytest.mark.parametrize("platform", COMPOSITE_PLATFORMS)
async def test_every_kind_through_its_page(
    hass: HomeAssistant, flow_entry: MockConfigEntry, platform: str
) -> None:
    """Every kind of several addresses is built through its one page, each role it has given."""
    kind = KINDS[platform]
    walk = await entity_page(hass, flow_entry, platform)
    assert set(sections_of(walk.result)) == {*kind.sections, "entity_options"}
    values: dict[str, Any] = {"name": "Unit"}
    addresses = iter(f"VW{200 + 2 * index}" for index in range(20))
    bits = iter(("Q0.4", "Q0.5", "Q0.6", "Q0.7", "Q1.0"))
    inputs = iter(("I0.1", "I0.2", "I0.3", "I0.4"))
    for name, roles in kind.sections.items():
        given = values.setdefault(name, {})
        for role in roles:
            if role.checked_as == "button":
                given[role.key] = next(bits)
            elif role.checked_as == "binary_sensor":
                given[role.key] = next(inputs)
            elif role.checked_as == "switch":
                given[role.key] = next(bits)
            else:
                given[role.key] = next(addresses)
            if role.labels:
                given[f"{role.key}_value_map"] = f"0={role.labels[0]};1={role.labels[1]}"
            elif "value_map" in role.asks:
                given[f"{role.key}_value_map"] = "0=Comfort;1=Eco"
    menu = await walk.fill(values)
    assert menu["step_id"] == "menu", menu.get("errors")
    assert walk.pages == 3  # the menu, the kind, the page
    await step(hass, menu, {"next_step_id": "save"})
    parts = stored(flow_entry)
    assert set(parts) == set(kind.role_keys)
    for role in kind.roles:
        assert parts[role.key]["read_only"] is not role.written


async def test_errors_on_their_field_or_section(
    hass: HomeAssistant, flow_entry: MockConfigEntry
) -> None:
    """A bad value is refused where it was given, its section opened; nothing is added."""
    walk = await entity_page(hass, flow_entry, "cover")
    result = await walk.fill({**COVER, "name": " "})
    assert result["errors"] == {"name": "name_required"}
    result = await walk.fill({**COVER, "commands": {"open": "IW0"}})
    assert list(result["errors"]) == ["commands"]
    assert problem(result, "commands") == "address_not_writable"
    assert result["description_placeholders"]["commands_role"] == "Open command"
    assert result["description_placeholders"]["commands_problem"].startswith("IW0 can never")
    result = await walk.fill({**COVER, "limits": {"status": "VW50"}})
    assert list(result["errors"]) == ["limits"]
    assert problem(result, "limits") == "map_empty"
    result = await walk.fill({**COVER, "position": {"position": "VW40", "raw_min": 0}})
    assert problem(result, "position") == "linear_incomplete"
    assert not sections_of(result)["position"].options["collapsed"]
    result = await walk.fill({**COVER, "travel_time": 5000})
    assert result["errors"] == {"travel_time": "travel_time_out_of_range"}
    result = await walk.fill({"name": "Shutter", "tilt": {"tilt_position": "VW60"}})
    assert result["errors"] == {"base": "role_missing"}
    assert "open command" in result["description_placeholders"]["roles"]
    result = await walk.fill({**COVER, "commands": {"open": "Q0.4", "close": "Q0.4"}})
    assert problem(result, "commands") == "already_configured"
    assert result["description_placeholders"]["commands_role"] == "Close command"
    position = {"position": "VW40", "raw_min": 0, "raw_max": 27648}
    menu = await walk.fill({**COVER, "position": position})
    assert menu["step_id"] == "menu", menu.get("errors")
    await step(hass, menu, {"next_step_id": "save"})
    parts = stored(flow_entry)
    assert (parts["position"]["raw_max"], parts["position"]["shown_max"]) == (27648.0, 100.0)
    assert (parts["position"]["raw_min"], parts["position"]["shown_min"]) == (0.0, 0.0)


async def test_climate_map_and_needs(hass: HomeAssistant, flow_entry: MockConfigEntry) -> None:
    """A mode map naming no Home Assistant mode is refused on its section; an action alone shows
    nothing and the page says which parts it needs."""
    walk = await entity_page(hass, flow_entry, "climate")
    result = await walk.fill({"name": "Boiler", "action": {"hvac_action": "VW56"}})
    assert problem(result, "action") == "map_empty"
    action = {"hvac_action": "VW56", "hvac_action_value_map": "0=idle;1=heating"}
    result = await walk.fill({"name": "Boiler", "action": action})
    assert result["errors"] == {"base": "role_missing"}
    modes = {"hvac_mode": "VW54", "hvac_mode_value_map": "0=off;1=warm"}
    result = await walk.fill({"name": "Boiler", "modes": modes})
    assert problem(result, "modes") == "role_labels"
    labels = result["description_placeholders"]["labels"].split(", ")
    assert "heat" in labels
    assert "opening" not in labels  # a climate's modes, not a cover's states
    modes["hvac_mode_value_map"] = "0=Off;1=HEAT"  # any case
    menu = await walk.fill({"name": "Boiler", "modes": modes})
    assert menu["step_id"] == "menu", menu.get("errors")


async def test_edit_a_part(hass: HomeAssistant, flow_entry: MockConfigEntry) -> None:
    """Editing a part asks its address and settings again, keeps its role and its entity."""
    walk = await entity_page(hass, flow_entry, "switch")
    on_off = {"state": "Q0.3", "command": "M1.1", "pulse": 0.5}
    menu = await walk.fill({"name": "Hall", "on_off": on_off})
    points = await saved(hass, flow_entry, menu)
    (command,) = (pid for pid, data in points.items() if data["role"] == "command")
    assert points[command]["pulse"] == 0.5
    menu = await hass.config_entries.subentries.async_init(
        (flow_entry.entry_id, SUBENTRY_DEVICE),
        context={"source": "reconfigure", "subentry_id": next(iter(flow_entry.subentries))},
    )
    result = await step(hass, menu, {"next_step_id": "edit"})
    result = await step(hass, result, {"point": command})
    assert result["step_id"] == "composite_entity"
    page = page_shown(result)
    assert page["on_off"] == {
        "state": "Q0.3",
        "state_data_type": points[next(iter(points))]["data_type"],
        "command": "M1.1",  # its own address is not taken
        "command_data_type": points[command]["data_type"],
        "pulse": 0.5,
    }
    page["on_off"].pop("pulse")
    menu = await step(hass, result, page)
    assert menu["type"] is FlowResultType.MENU, menu.get("errors")
    points = await saved(hass, flow_entry, menu)
    assert "pulse" not in points[command]
    assert points[command]["role"] == "command"
    assert len({data["entity"] for data in points.values()}) == 1


async def saved(hass: HomeAssistant, flow_entry: MockConfigEntry, menu: Any) -> dict[str, Any]:
    """Save the machine from its menu; return its stored points."""
    await step(hass, menu, {"next_step_id": "save"})
    (device,) = flow_entry.subentries.values()
    return dict(device.data[CONF_POINTS])
