"""One validation of an expose at every door: floors of cooldown and resend, feedback at depth."""

from __future__ import annotations

from typing import Any

from homeassistant.config_entries import ConfigSubentry
from homeassistant.const import CONF_HOST, CONF_PORT
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import CONF_VENDOR, DOMAIN
from custom_components.plc_bridge.model.expose import check_expose
from custom_components.plc_bridge.plc.vendors import client_class
from tests.entries import device, point
from tests.flows.forms import error_message
from tests.flows.test_expose_flow import EXPOSE, OUTDOOR, exposes, plc_entry, start, submit
from tests.harness import expose_data


@pytest.mark.parametrize(
    ("settings", "field", "error"),
    [
        ({"cooldown": 0}, "cooldown", "cooldown_too_short"),
        ({"cooldown": 0.05}, "cooldown", "cooldown_too_short"),
        ({"resend": 0.001}, "resend", "resend_too_short"),
        ({"resend": 0.5}, "resend", "resend_too_short"),
        ({"cooldown": 0.1, "resend": 0}, None, None),
        ({"cooldown": 0.1, "resend": 1}, None, None),
    ],
    ids=["cooldown 0", "cooldown 50 ms", "resend 1 ms", "resend 0.5 s", "floors", "resend 1 s"],
)
async def test_floors_on_their_field(
    hass: HomeAssistant, settings: dict[str, Any], field: str | None, error: str | None
) -> None:
    """A cooldown under 0.1 s (0 too) and a resend under 1 s (but 0: none) are refused."""
    entry = plc_entry(hass)
    result = await submit(hass, await start(hass, entry), OUTDOOR | settings)
    if field is None:
        assert result["type"] is FlowResultType.CREATE_ENTRY
        return
    assert result["errors"] == {field: error}
    assert error_message(result, field, *EXPOSE)
    assert not exposes(entry)


def loop_entry(hass: HomeAssistant, depth: int) -> tuple[MockConfigEntry, list[str]]:
    """Add a PLC whose numbers n0..n{depth-1} show VW30, VW32, ...; exposes n1->VW34 ... stored.

    Expose i sends n(i) to the address of n(i+1); the last one closes the loop at n0.
    """
    points = [point(f"n{i}", f"N{i}", "number", f"VW{30 + 2 * i}", "signed") for i in range(depth)]
    entry = MockConfigEntry(
        domain=DOMAIN,
        data={CONF_VENDOR: "s7_smart", CONF_HOST: "192.0.2.1", CONF_PORT: 443},
        version=2,
        subentries_data=[device(points)],
    )
    entry.add_to_hass(hass)
    registry = er.async_get(hass)
    ids = [
        registry.async_get_or_create("number", DOMAIN, f"plc_n{i}", config_entry=entry).entity_id
        for i in range(depth)
    ]
    for i in range(1, depth):
        data = expose_data(ids[i], (f"VW{30 + 2 * ((i + 1) % depth)}", "signed"))
        hass.config_entries.async_add_subentry(entry, _subentry(data, f"e{i}"))
    return entry, ids


def _subentry(data: dict[str, Any], subentry_id: str) -> ConfigSubentry:
    """Return an expose subentry holding the data."""
    return ConfigSubentry(
        data=data,
        subentry_id=subentry_id,
        subentry_type="expose",
        title=subentry_id,
        unique_id=None,
    )


@pytest.mark.parametrize("depth", [2, 3, 4])
async def test_feedback_at_any_depth(hass: HomeAssistant, depth: int) -> None:
    """Exposes that feed each other through our entities are refused, however long the loop.

    Two exposes feeding each other ran a word from 3 to 12,288 when only one hop was looked at.
    """
    entry, ids = loop_entry(hass, depth)
    closing = {"address": "VW32", "data_type": "signed"}
    result = await submit(hass, await start(hass, entry, ids[0]), closing)
    assert result["errors"] == {"address": "expose_feeds_back"}
    assert "VW32" in error_message(result, "address", *EXPOSE)
    assert len(exposes(entry)) == depth - 1
    elsewhere = closing | {"address": "VW60"}
    result = await submit(hass, await start(hass, entry, ids[0]), elsewhere)
    assert result["type"] is FlowResultType.CREATE_ENTRY


def test_one_validation_without_entities() -> None:
    """The file's door calls the same function, without the entities it cannot know yet."""
    client = client_class("s7_smart")
    values = expose_data("sensor.outdoor", ("VW10", "signed")) | {"cooldown": 0.0}
    _data, errors, _words = check_expose(client, values)
    assert errors == {"cooldown": "cooldown_too_short"}
