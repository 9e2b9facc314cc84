"""The expose subentry flow: two pages (the entity, then its attribute, address and the rest),
checked like a point's address, stored, edited."""

from __future__ import annotations

from typing import Any

from homeassistant.config_entries import SOURCE_USER
from homeassistant.const import CONF_HOST, CONF_PORT
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import entity_registry as er
from homeassistant.helpers.selector import (
    AttributeSelector,
    BooleanSelector,
    EntitySelector,
    NumberSelector,
    SelectSelector,
    TextSelector,
)
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.config_flow import PlcBridgeConfigFlow
from custom_components.plc_bridge.const import CONF_VENDOR, DOMAIN, SUBENTRY_EXPOSE
from custom_components.plc_bridge.flows.expose_flow import ExposeSubentryFlowHandler
from tests.entries import device, point
from tests.flows.forms import error_message, suggested, translated
from tests.harness import add_expose

pytestmark = pytest.mark.no_pacing

EXPOSE = ("config_subentries", SUBENTRY_EXPOSE)
OUTDOOR = {"address": "vd400", "data_type": "float"}


def plc_entry(hass: HomeAssistant, vendor: str = "s7_smart") -> MockConfigEntry:
    """Add a PLC entry (not set up) with a machine holding a read-only word VW10."""
    entry = MockConfigEntry(
        domain=DOMAIN,
        data={CONF_VENDOR: vendor, CONF_HOST: "192.0.2.1", CONF_PORT: 443},
        version=2,
        subentries_data=[
            device([point("level", "Level", "sensor", "VW10", "signed", read_only=True)])
        ],
    )
    entry.add_to_hass(hass)
    return entry


async def start(
    hass: HomeAssistant, entry: MockConfigEntry, entity_id: str = "sensor.outdoor"
) -> Any:
    """Open a new expose, pick the entity on the first page; return the second page."""
    result = translated(
        await hass.config_entries.subentries.async_init(
            (entry.entry_id, SUBENTRY_EXPOSE), context={"source": SOURCE_USER}
        ),
        *EXPOSE,
    )
    assert result["step_id"] == "entity"
    result = await submit(hass, result, {"entity_id": entity_id})
    assert result["step_id"] == "expose"
    return result


async def submit(hass: HomeAssistant, result: Any, values: dict[str, Any]) -> Any:
    """Submit the expose form; check its texts."""
    return translated(
        await hass.config_entries.subentries.async_configure(result["flow_id"], values), *EXPOSE
    )


def exposes(entry: MockConfigEntry) -> list[Any]:
    """Return the entry's expose subentries."""
    return [s for s in entry.subentries.values() if s.subentry_type == SUBENTRY_EXPOSE]


def test_registered() -> None:
    """The config flow offers the expose subentry type beside machines."""
    types = PlcBridgeConfigFlow.async_get_supported_subentry_types(MockConfigEntry(domain=DOMAIN))
    assert types[SUBENTRY_EXPOSE] is ExposeSubentryFlowHandler


async def test_add_an_expose(hass: HomeAssistant) -> None:
    """A valid form is stored with the vendor's spelling of the address and a normal map."""
    hass.states.async_set("weather.home", "sunny", {"temperature": 21.5})
    entry = plc_entry(hass)
    result = await start(hass, entry, "weather.home")
    result = await submit(
        hass, result, OUTDOOR | {"value_map": " on = 1 ; off=0 ", "attribute": "temperature"}
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    (subentry,) = exposes(entry)
    assert subentry.title == "weather.home (temperature) → VD400"
    assert subentry.data == {
        "entity_id": "weather.home",
        "attribute": "temperature",
        "address": "VD400",
        "data_type": "float",
        "scale": 1.0,
        "offset": 0.0,
        "value_map": "on=1;off=0",
        "cooldown": 1.0,
        "resend": 0.0,
        "send_on_start": True,
    }


@pytest.mark.parametrize(
    ("changes", "field", "error", "message"),
    [
        ({"address": "VX1"}, "address", "invalid_address", "Invalid address: "),
        ({"address": "I0.0", "data_type": "signed"}, "address", "address_not_writable", "I0.0"),
        ({"address": "VB11", "data_type": "signed"}, "address", "expose_read_only", "VB11"),
        ({"address": "DATE", "data_type": "signed"}, "data_type", "expose_data_type", ""),
        ({"scale": 0.0}, "scale", "scale_zero", ""),
        ({"value_map": "on"}, "value_map", "map_not_a_pair", '"on"'),
        ({"value_map": "on=1;ON=2"}, "value_map", "map_repeated", '"ON=2"'),
        ({"default": "warm"}, "default", "invalid_default", "warm"),
    ],
)
async def test_refused_on_its_field(
    hass: HomeAssistant, changes: dict[str, Any], field: str, error: str, message: str
) -> None:
    """A bad field is refused on that field with a translated message; nothing is stored."""
    entry = plc_entry(hass)
    result = await start(hass, entry)
    result = await submit(hass, result, OUTDOOR | changes)
    assert result["type"] is FlowResultType.FORM
    assert result["errors"] == {field: error}
    assert message in error_message(result, field, *EXPOSE)
    assert not exposes(entry)


async def test_one_expose_per_address(hass: HomeAssistant) -> None:
    """A second expose to the same address is refused; editing the first keeps its address."""
    entry = plc_entry(hass)
    subentry_id = add_expose(hass, entry, "sensor.outdoor", ("VD400", "float"))
    result = await start(hass, entry, "sensor.other")
    result = await submit(hass, result, OUTDOOR)
    assert result["errors"] == {"address": "already_configured"}
    result = translated(await entry.start_subentry_reconfigure_flow(hass, subentry_id), *EXPOSE)
    assert suggested(result, "entity_id") == "sensor.outdoor"
    result = await submit(hass, result, {"entity_id": "sensor.outdoor"})
    assert suggested(result, "address") == "VD400"
    result = await submit(hass, result, OUTDOOR | {"cooldown": 5.0, "resend": 60.0})
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "reconfigure_successful"
    (subentry,) = exposes(entry)
    assert subentry.data["cooldown"] == 5.0
    assert subentry.data["resend"] == 60.0


@pytest.mark.parametrize(
    ("vendor", "address", "data_type", "stored"),
    [
        ("tecomat", "plcData.varReal", "REAL", "plcData.varReal"),
        ("plcnext", "MainInstance.Setpoint", "REAL", "Arp.Plc.Eclr/MainInstance.Setpoint"),
        ("softplc", "F8:1", "REAL", "F8:1"),
        ("s7", "db1.dbd200", "REAL", "DB1.DBD200"),
    ],
)
async def test_other_vendors(
    hass: HomeAssistant, vendor: str, address: str, data_type: str, stored: str
) -> None:
    """Each vendor's parser checks and spells the address; a bad one is refused."""
    entry = plc_entry(hass, vendor)
    result = await start(hass, entry)
    bad = await submit(hass, result, {"address": "%%", "data_type": data_type})
    assert bad["errors"] == {"address": "invalid_address"}
    result = await submit(hass, bad, {"address": address, "data_type": data_type})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert exposes(entry)[0].data["address"] == stored


@pytest.mark.parametrize(
    ("address", "data_type"),
    [("vd400", "unsigned"), ("VW402", "signed"), ("VB403", "unsigned")],
)
async def test_one_expose_per_address_whatever_its_type(
    hass: HomeAssistant, address: str, data_type: str
) -> None:
    """An address another expose writes, under another data type or overlapping it, is refused:
    both in one write would leave the PLC holding whichever the request put last."""
    entry = plc_entry(hass)
    add_expose(hass, entry, "sensor.outdoor", ("VD400", "float"))
    result = await start(hass, entry, "sensor.other")
    values = {"address": address, "data_type": data_type}
    result = await submit(hass, result, values)
    assert result["errors"] == {"address": "already_configured"}
    assert len(exposes(entry)) == 1
    result = await submit(hass, result, values | {"address": "VW404"})
    assert result["type"] is FlowResultType.CREATE_ENTRY


async def test_own_entity_to_its_own_address_refused(hass: HomeAssistant) -> None:
    """An entity of this PLC sent to an address it reads would feed back: refused on the address.

    Sent elsewhere, or another integration's entity sent to that address, it is taken.
    """
    setpoint = point("setpoint", "Setpoint", "number", "VD100", "float")
    parts = [
        point("c1", "Room", "climate", "VW20", "signed", role="target_temperature", entity="c1"),
        point("c2", "Room", "climate", "VW22", "signed", role="current_temperature", entity="c1"),
    ]
    entry = MockConfigEntry(
        domain=DOMAIN,
        data={CONF_VENDOR: "s7_smart", CONF_HOST: "192.0.2.1", CONF_PORT: 443},
        version=2,
        subentries_data=[device([setpoint, *parts])],
    )
    entry.add_to_hass(hass)
    registry = er.async_get(hass)
    number = registry.async_get_or_create("number", DOMAIN, "plc_setpoint", config_entry=entry)
    climate = registry.async_get_or_create("climate", DOMAIN, "plc_c1", config_entry=entry)
    cases = [
        (number.entity_id, "VD100", "float", "expose_feeds_back"),
        (climate.entity_id, "VB22", "unsigned", "expose_feeds_back"),  # inside a part's word
        (number.entity_id, "VD104", "float", None),
        ("sensor.outdoor", "VD100", "float", None),
    ]
    for entity_id, address, data_type, error in cases:
        result = await start(hass, entry, entity_id)
        values = {"address": address, "data_type": data_type}
        result = await submit(hass, result, values)
        if error is None:
            assert result["type"] is FlowResultType.CREATE_ENTRY, (entity_id, address)
            continue
        assert result["errors"] == {"address": error}, (entity_id, address)
        assert address in error_message(result, "address", *EXPOSE)


async def test_attribute_the_entity_lacks(hass: HomeAssistant) -> None:
    """An attribute the entity lacks now is told with those it has; submitted again, it is kept."""
    hass.states.async_set("sun.sun", "above_horizon", {"azimuth": 180.5, "elevation": 30.0})
    entry = plc_entry(hass)
    values = {"attribute": "azimut", "address": "VD400", "data_type": "float"}
    result = await submit(hass, await start(hass, entry, "sun.sun"), values)
    assert result["errors"] == {"attribute": "expose_attribute_missing"}
    message = error_message(result, "attribute", *EXPOSE)
    assert '"azimut"' in message
    assert "azimuth, elevation" in message
    assert not exposes(entry)
    result = await submit(hass, result, values)
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert exposes(entry)[0].data["attribute"] == "azimut"
    result = await submit(
        hass, await start(hass, entry, "sun.sun"), values | {"attribute": "azimuth"}
    )
    assert result["errors"] == {"address": "already_configured"}  # the attribute itself passed


TYPED = (TextSelector, NumberSelector)
"""Fields a user types into; the others are picked with a click."""
PICKED = (EntitySelector, AttributeSelector, SelectSelector, BooleanSelector)
SUN = {"azimuth": 180.5, "elevation": 30.0, "friendly_name": "Sun"}


def fields(result: Any) -> dict[str, Any]:
    """Return a form's selectors by field."""
    return {str(marker): selector for marker, selector in result["data_schema"].schema.items()}


async def test_two_pages_and_one_typed_field(hass: HomeAssistant) -> None:
    """From the PLC's entry to a stored expose of an attribute: two pages, the entity and its
    attribute picked from lists, the address the only field typed (issue 25's count)."""
    hass.states.async_set("sun.sun", "above_horizon", SUN)
    entry = plc_entry(hass)
    answers = [
        {"entity_id": "sun.sun"},
        {"attribute": "azimuth", "address": "VD400", "data_type": "float"},
    ]
    result = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_EXPOSE), context={"source": SOURCE_USER}
    )
    pages: list[str] = []
    typed: list[str] = []
    picked: list[str] = []
    while result["type"] is FlowResultType.FORM:
        form = fields(translated(result, *EXPOSE))
        values = answers[len(pages)]
        pages.append(result["step_id"])
        for key in values:
            assert isinstance(form[key], TYPED + PICKED), key
            (typed if isinstance(form[key], TYPED) else picked).append(key)
        if "attribute" in form:
            attribute = form["attribute"]
        result = await hass.config_entries.subentries.async_configure(result["flow_id"], values)
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert pages == ["entity", "expose"]
    assert typed == ["address"]
    assert picked == ["entity_id", "attribute", "data_type"]
    assert isinstance(attribute, AttributeSelector)
    assert attribute.config["entity_id"] == "sun.sun"
    assert "friendly_name" in attribute.config["hide_attributes"]
    (subentry,) = exposes(entry)
    assert subentry.title == "sun.sun (azimuth) → VD400"
    assert subentry.data == {
        "entity_id": "sun.sun",
        "attribute": "azimuth",
        "address": "VD400",
        "data_type": "float",
        "scale": 1.0,
        "offset": 0.0,
        "cooldown": 1.0,
        "resend": 0.0,
        "send_on_start": True,
    }


@pytest.mark.parametrize(
    "attributes", [None, {}, {"friendly_name": "Away", "editable": True, "icon": "mdi:home"}]
)
async def test_attribute_left_out_when_the_entity_has_none(
    hass: HomeAssistant, attributes: dict[str, Any] | None
) -> None:
    """An entity without attributes worth sending (or not there yet) still gets the second page,
    without the attribute: its state is sent."""
    if attributes is not None:
        hass.states.async_set("input_boolean.away", "on", attributes)
    entry = plc_entry(hass)
    result = await start(hass, entry, "input_boolean.away")
    assert "attribute" not in fields(result)
    assert "address" in fields(result)
    result = await submit(hass, result, {"address": "M10.0", "data_type": "signed"})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert "attribute" not in exposes(entry)[0].data


async def test_reconfigure_suggests_the_stored_attribute(hass: HomeAssistant) -> None:
    """Editing goes through the same two pages with the stored values suggested; the attribute is
    suggested for its own entity only, and kept while the entity has no attributes."""
    hass.states.async_set("sun.sun", "above_horizon", SUN)
    hass.states.async_set("weather.home", "sunny", {"temperature": 21.5})
    entry = plc_entry(hass)
    subentry_id = add_expose(hass, entry, "sun.sun", ("VD400", "float"), attribute="azimuth")

    async def edit(entity_id: str) -> Any:
        """Open the edit of the expose, pick `entity_id`; return the second page."""
        result = translated(await entry.start_subentry_reconfigure_flow(hass, subentry_id), *EXPOSE)
        assert result["step_id"] == "entity"
        assert suggested(result, "entity_id") == "sun.sun"
        result = await submit(hass, result, {"entity_id": entity_id})
        assert result["step_id"] == "expose"
        return result

    result = await edit("sun.sun")
    assert suggested(result, "attribute") == "azimuth"
    assert suggested(result, "address") == "VD400"
    assert fields(result)["attribute"].config["entity_id"] == "sun.sun"
    result = await edit("weather.home")
    assert suggested(result, "attribute") is None
    assert fields(result)["attribute"].config["entity_id"] == "weather.home"
    hass.states.async_remove("sun.sun")
    result = await edit("sun.sun")
    assert suggested(result, "attribute") == "azimuth"
    values = {str(m): suggested(result, str(m)) for m in result["data_schema"].schema}
    values = {key: value for key, value in values.items() if value is not None}
    cleared = {key: value for key, value in values.items() if key != "attribute"}
    result = await submit(hass, result, cleared | {"address": "VX1"})
    assert result["errors"] == {"address": "invalid_address"}
    assert "attribute" in fields(result)  # still there to pick again
    result = await submit(hass, result, values | {"cooldown": 5.0})
    assert result["reason"] == "reconfigure_successful"
    assert entry.subentries[subentry_id].data["attribute"] == "azimuth"
    assert entry.subentries[subentry_id].data["cooldown"] == 5.0
