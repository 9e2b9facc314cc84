"""Options flow: the poll interval, never shorter than the vendor's advised request rate."""

from __future__ import annotations

from homeassistant.const import CONF_SCAN_INTERVAL
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import DOMAIN
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from simulators.s7_smart import S7SmartSimulator
from tests.entries import PointData, device, point, sim_data
from tests.flows.forms import error_message, polling_form, suggested, translated

pytestmark = pytest.mark.no_pacing

OPTIONS = ("options",)


def words(count: int) -> list[PointData]:
    """Return `count` word sensors."""
    return [point(f"w{i}", f"Word {i}", "sensor", f"VW{2 * i}", "signed") for i in range(count)]


@pytest.fixture
def paced(monkeypatch: pytest.MonkeyPatch) -> None:
    """Restore the S7-200 SMART's advised pace of one request a second."""
    monkeypatch.setattr(S7SmartClient, "request_interval", 1.0)


@pytest.mark.usefixtures("paced")
async def test_minimum_follows_the_points(hass: HomeAssistant, flow_sim: S7SmartSimulator) -> None:
    """100 points take 4 requests at most one a second: at least 4 s between polls."""
    entry = MockConfigEntry(
        domain=DOMAIN,
        data=sim_data(flow_sim),
        subentries_data=[device(words(100))],
        version=2,
    )
    entry.add_to_hass(hass)
    result = translated(await polling_form(hass, entry), *OPTIONS)
    assert result["step_id"] == "polling"
    assert suggested(result, CONF_SCAN_INTERVAL) == 10.0
    assert result["description_placeholders"] == {
        "minimum": "4",
        "fast_minimum": "1",
        "points": "100",
        "requests": "4",
        "cycle": "10",
    }
    result = translated(
        await hass.config_entries.options.async_configure(
            result["flow_id"], {CONF_SCAN_INTERVAL: 3.5}
        ),
        *OPTIONS,
    )
    assert result["errors"] == {CONF_SCAN_INTERVAL: "scan_interval_too_short"}
    assert "at most every 4 s" in error_message(result, CONF_SCAN_INTERVAL, *OPTIONS)
    assert suggested(result, CONF_SCAN_INTERVAL) == 3.5
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {CONF_SCAN_INTERVAL: 4}
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert dict(entry.options) == {CONF_SCAN_INTERVAL: 4.0}


@pytest.mark.usefixtures("paced")
async def test_current_interval_suggested(hass: HomeAssistant, flow_sim: S7SmartSimulator) -> None:
    """Without points one request a poll: 1 s; the stored interval is suggested."""
    entry = MockConfigEntry(
        domain=DOMAIN, data=sim_data(flow_sim), options={CONF_SCAN_INTERVAL: 2.5}
    )
    entry.add_to_hass(hass)
    result = await polling_form(hass, entry)
    assert suggested(result, CONF_SCAN_INTERVAL) == 2.5
    assert result["description_placeholders"]["minimum"] == "1"
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {CONF_SCAN_INTERVAL: 1}
    )
    assert dict(entry.options) == {CONF_SCAN_INTERVAL: 1.0}
