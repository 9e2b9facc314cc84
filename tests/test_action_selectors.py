"""The write and read actions: one point in fields with Home Assistant selectors, or a list.

The action's form offers the PLC (config entry selector of PLC Bridge), the address (text), the
data type (a select with the data types' labels) and, to write, the value; scripts keep the
list of points. One point or a list, never both, never neither.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from homeassistant.core import HomeAssistant
from homeassistant.exceptions import ServiceValidationError
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
import yaml

from custom_components.plc_bridge.const import DOMAIN
from custom_components.plc_bridge.plc.vendors import client_class, implemented
from simulators.s7_smart import S7SmartSimulator
from tests.entries import call
from tests.flows.forms import strings_at

pytestmark = pytest.mark.no_pacing

SERVICES = yaml.safe_load(
    (
        Path(__file__).resolve().parents[1] / "custom_components" / DOMAIN / "services.yaml"
    ).read_text(encoding="utf-8")
)


@pytest.mark.parametrize("action", ["write", "read"])
def test_fields_have_selectors(action: str) -> None:
    """The PLC, the address, the data type (labelled) and the value each have their selector;
    the list is optional, for scripts; every field is named and explained."""
    fields = SERVICES[action]["fields"]
    assert fields["config_entry_id"]["selector"] == {"config_entry": {"integration": DOMAIN}}
    assert fields["config_entry_id"]["required"] is True
    assert fields["address"]["selector"] == {"text": None}
    select = fields["data_type"]["selector"]["select"]
    assert select["translation_key"] == "data_type"
    every = {data_type for vendor in implemented() for data_type in client_class(vendor).data_types}
    assert set(select["options"]) == every
    labelled = strings_at("selector", "data_type", "options")
    assert {"signed", "unsigned", "float", "string", "raw"} <= set(labelled)
    assert ("value" in fields) == (action == "write")
    if action == "write":
        assert fields["value"]["selector"] == {"object": None}
    assert not any(
        field.get("required") for key, field in fields.items() if key != "config_entry_id"
    )
    texts = strings_at("services", action, "fields")
    assert set(texts) == set(fields)
    assert all(text["name"] and text["description"] for text in texts.values())


async def test_write_one_point_from_fields(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, setup_integration: MockConfigEntry
) -> None:
    """Address, data type and value as the form sends them write that one point."""
    await call(hass, "write", setup_integration, address="VW30", data_type="signed", value=-5)
    assert s7_smart_ha_sim.calls["write"] == 1
    assert s7_smart_ha_sim.get("VW30") == -5


async def test_read_one_point_from_fields(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, setup_integration: MockConfigEntry
) -> None:
    """Address and data type as the form sends them read that one point."""
    response = await call(hass, "read", setup_integration, address="VD100", data_type="float")
    assert response == {"values": {"VD100": 21.5}, "errors": {}}


@pytest.mark.parametrize(
    ("action", "data", "key"),
    [
        ("write", {}, "one_point_or_list"),
        (
            "write",
            {
                "address": "VW30",
                "data_type": "signed",
                "value": 1,
                "points": [{"address": "VW32", "data_type": "signed", "value": 2}],
            },
            "one_point_or_list",
        ),
        ("write", {"address": "VW30", "data_type": "signed"}, "point_incomplete"),
        ("write", {"address": "VW30", "value": 1}, "point_incomplete"),
        ("read", {}, "one_point_or_list"),
        ("read", {"data_type": "float"}, "point_incomplete"),
    ],
)
async def test_one_point_or_a_list(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    setup_integration: MockConfigEntry,
    *,
    action: str,
    data: dict[str, Any],
    key: str,
) -> None:
    """Both, neither or a point lacking a field: refused with a clear message, nothing sent."""
    before = dict(s7_smart_ha_sim.calls)
    with pytest.raises(ServiceValidationError) as err:
        await call(hass, action, setup_integration, **data)
    assert err.value.translation_key == key
    message = strings_at("exceptions", key, "message")
    assert str(err.value) == message.format(**(err.value.translation_placeholders or {}))
    assert s7_smart_ha_sim.calls.get("write", 0) == before.get("write", 0)
    assert s7_smart_ha_sim.calls.get("read", 0) == before.get("read", 0)
    assert s7_smart_ha_sim.get("VW30") == 0
