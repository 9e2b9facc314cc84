"""Point subentries: the vendor's parser checks the address, platforms fit the point."""

from __future__ import annotations

from types import MappingProxyType
from typing import Any

from homeassistant.components.sensor import SensorStateClass
from homeassistant.config_entries import SOURCE_RECONFIGURE, SOURCE_USER, ConfigSubentry
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import CONF_PLATFORM, POINT_PLATFORMS, SUBENTRY_POINT
from custom_components.plc_bridge.plc import TlsMode
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from tests.flow_fixtures import STRINGS, error_message, strings_at, suggested, translated

POINTS = ("config_subentries", SUBENTRY_POINT)


def point_input(**changes: Any) -> dict[str, Any]:
    """Return the point form input of a signed word sensor, with changes."""
    values = {
        "name": "Boiler temperature",
        "platform": "sensor",
        "address": "vw100",
        "data_type": "signed",
        "scale": 0.1,
        "offset": 0,
        "read_only": True,
    }
    return values | changes


async def open_form(hass: HomeAssistant, entry: MockConfigEntry) -> Any:
    """Start adding a point; return the point form."""
    result = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_POINT), context={"source": SOURCE_USER}
    )
    return translated(result, *POINTS)


async def submit(hass: HomeAssistant, result: Any, values: dict[str, Any]) -> Any:
    """Submit a point form and check the answer is translated."""
    return translated(
        await hass.config_entries.subentries.async_configure(result["flow_id"], values), *POINTS
    )


async def test_add_point(hass: HomeAssistant, flow_entry: MockConfigEntry) -> None:
    """A valid point becomes a subentry with its normalized address and unique id."""
    result = await open_form(hass, flow_entry)
    assert result["step_id"] == "user"
    types = result["data_schema"].schema["data_type"].config["options"]
    assert types == list(S7SmartClient.data_types)
    result = await submit(
        hass, result, point_input(unit_of_measurement="°C", device_class="temperature", min=0)
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    (subentry,) = flow_entry.subentries.values()
    assert subentry.title == "Boiler temperature"
    assert subentry.unique_id == "VW100|signed"
    assert dict(subentry.data) == {
        "platform": "sensor",
        "address": "VW100",
        "data_type": "signed",
        "unit_of_measurement": "°C",
        "device_class": "temperature",
        "scale": 0.1,
        "offset": 0.0,
        "min": 0.0,
        "read_only": True,
    }
    result = await submit(hass, await open_form(hass, flow_entry), point_input(address="VW100"))
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "already_configured"
    assert len(flow_entry.subentries) == 1


async def test_invalid_address_shows_the_parser_message(
    hass: HomeAssistant, flow_entry: MockConfigEntry
) -> None:
    """The vendor parser's message is the error text on the address field."""
    result = await submit(hass, await open_form(hass, flow_entry), point_input(address="VW20480"))
    assert result["errors"] == {"address": "invalid_address"}
    assert error_message(result, "address", *POINTS) == (
        "Invalid address: VW20480 is outside V memory (0..20479)"
    )
    result = await submit(hass, result, point_input(address="VD0", data_type="string"))
    assert error_message(result, "address", *POINTS).startswith("Invalid address: VD0 cannot")
    assert not flow_entry.subentries


@pytest.mark.parametrize(
    ("changes", "errors"),
    [
        ({"platform": "switch"}, {CONF_PLATFORM: "needs_bool"}),
        (
            {"platform": "binary_sensor", "address": "VD4", "data_type": "float"},
            {CONF_PLATFORM: "needs_bool"},
        ),
        (
            {"platform": "number", "address": "VB0", "data_type": "string"},
            {CONF_PLATFORM: "needs_number"},
        ),
        (
            {"platform": "number", "address": "VB0", "data_type": "raw"},
            {CONF_PLATFORM: "needs_number"},
        ),
        ({"platform": "datetime"}, {CONF_PLATFORM: "needs_datetime"}),
        ({"device_class": "outlet"}, {"device_class": "invalid_device_class"}),
        (
            {"platform": "switch", "address": "Q0.1", "state_class": "measurement"},
            {"state_class": "state_class_numeric_sensor"},
        ),
        (
            {"address": "VB0", "data_type": "string", "state_class": "total"},
            {"state_class": "state_class_numeric_sensor"},
        ),
        ({"scale": 0}, {"scale": "scale_zero"}),
        ({"min": 10, "max": 10}, {"max": "max_not_above_min"}),
    ],
)
async def test_point_refused(
    hass: HomeAssistant,
    flow_entry: MockConfigEntry,
    changes: dict[str, Any],
    errors: dict[str, str],
) -> None:
    """Platforms must fit the point's kind of value; device and state classes the platform."""
    result = await submit(hass, await open_form(hass, flow_entry), point_input(**changes))
    assert result["step_id"] == "user"
    assert result["errors"] == errors
    assert not flow_entry.subentries


async def test_platform_error_names_the_point(
    hass: HomeAssistant, flow_entry: MockConfigEntry
) -> None:
    """The platform error says which point does not fit, normalized."""
    result = await submit(
        hass, await open_form(hass, flow_entry), point_input(platform="switch", address="mw4")
    )
    assert error_message(result, CONF_PLATFORM, *POINTS) == (
        "Binary sensors and switches need a true/false point; MW4 as signed is not one."
    )


@pytest.mark.parametrize(
    ("changes", "data"),
    [
        (
            {"platform": "switch", "address": "q0.1", "device_class": "outlet", "read_only": False},
            {"address": "Q0.1", "device_class": "outlet", "read_only": False},
        ),
        ({"platform": "binary_sensor", "address": "V10.3", "data_type": "unsigned"}, {}),
        (
            {"platform": "datetime", "address": "date", "read_only": False},
            {"address": "DATE", "read_only": False},
        ),
        (
            {"platform": "number", "address": "VD4", "data_type": "float", "max": 90, "step": 0.5},
            {"max": 90.0, "step": 0.5},
        ),
        ({"address": "VB0", "data_type": "string", "unit_of_measurement": ""}, {}),
    ],
)
async def test_point_accepted(
    hass: HomeAssistant, flow_entry: MockConfigEntry, changes: dict[str, Any], data: dict[str, Any]
) -> None:
    """Points whose platform fits are stored; empty optional fields are left out."""
    result = await submit(hass, await open_form(hass, flow_entry), point_input(**changes))
    assert result["type"] is FlowResultType.CREATE_ENTRY
    expected = {
        "platform": changes.get("platform", "sensor"),
        "address": changes["address"],
        "data_type": changes.get("data_type", "signed"),
        "scale": 0.1,
        "offset": 0.0,
        "read_only": True,
    }
    assert result["data"] == expected | data


@pytest.fixture
def two_points(flow_entry: MockConfigEntry, hass: HomeAssistant) -> list[str]:
    """Give the entry two word sensors; return their subentry ids."""
    for address in ("VW100", "VW102"):
        hass.config_entries.async_add_subentry(
            flow_entry,
            ConfigSubentry(
                data=MappingProxyType(
                    {
                        "platform": "sensor",
                        "address": address,
                        "data_type": "signed",
                        "unit_of_measurement": "W",
                    }
                ),
                subentry_type=SUBENTRY_POINT,
                title=f"Power {address}",
                unique_id=f"{address}|signed",
            ),
        )
    return list(flow_entry.subentries)


async def open_reconfigure(hass: HomeAssistant, entry: MockConfigEntry, subentry_id: str) -> Any:
    """Start editing a point; return its form."""
    result = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_POINT),
        context={"source": SOURCE_RECONFIGURE, "subentry_id": subentry_id},
    )
    return translated(result, *POINTS)


async def test_reconfigure_point(
    hass: HomeAssistant, flow_entry: MockConfigEntry, two_points: list[str]
) -> None:
    """Editing moves the point; the form starts from what is stored."""
    result = await open_reconfigure(hass, flow_entry, two_points[0])
    assert result["step_id"] == "reconfigure"
    assert suggested(result, "name") == "Power VW100"
    assert suggested(result, "unit_of_measurement") == "W"
    result = await submit(
        hass, result, point_input(name="Heat", address="vw104", data_type="unsigned")
    )
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "reconfigure_successful"
    subentry = flow_entry.subentries[two_points[0]]
    assert subentry.title == "Heat"
    assert subentry.unique_id == "VW104|unsigned"
    assert dict(subentry.data) == {
        "platform": "sensor",
        "address": "VW104",
        "data_type": "unsigned",
        "scale": 0.1,
        "offset": 0.0,
        "read_only": True,
    }


async def test_reconfigure_point_checks(
    hass: HomeAssistant, flow_entry: MockConfigEntry, two_points: list[str]
) -> None:
    """The same checks as adding: parser errors, another point's address; its own is fine."""
    result = await open_reconfigure(hass, flow_entry, two_points[0])
    result = await submit(hass, result, point_input(address="VW20480"))
    assert result["step_id"] == "reconfigure"
    assert result["errors"] == {"address": "invalid_address"}
    result = await submit(hass, result, point_input(address="VW102"))
    assert result["reason"] == "already_configured"
    result = await open_reconfigure(hass, flow_entry, two_points[0])
    result = await submit(hass, result, point_input(address="VW100"))
    assert result["reason"] == "reconfigure_successful"
    assert flow_entry.subentries[two_points[0]].unique_id == "VW100|signed"


def test_selector_options_translated() -> None:
    """Every option of the flow's selectors has an English label."""
    labels = {key: set(strings_at("selector", key, "options")) for key in STRINGS["selector"]}
    assert labels["platform"] == set(POINT_PLATFORMS)
    assert labels["state_class"] == set(SensorStateClass)
    assert labels["data_type"] >= set(S7SmartClient.data_types)
    assert labels["tls"] == set(TlsMode)
    assert labels["variable"] == {"manual"}
