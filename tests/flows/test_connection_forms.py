"""Connection forms: each vendor's pages have texts of their own, naming no other family."""

from __future__ import annotations

import re

from homeassistant.config_entries import SOURCE_USER
from homeassistant.const import CONF_HOST, CONF_PORT
from homeassistant.core import HomeAssistant
import pytest

from custom_components.plc_bridge.config_flow import PlcBridgeConfigFlow
from custom_components.plc_bridge.const import CONF_VENDOR, DOMAIN
from custom_components.plc_bridge.flows.connection_form import (
    connection_schema,
    connection_step,
    fields_schema,
    second_page,
)
from custom_components.plc_bridge.model.vendor_fields import SECOND_PAGES
from custom_components.plc_bridge.plc.vendors import client_class, implemented
from tests.flows.forms import strings_at

pytestmark = pytest.mark.no_pacing

STEPS = ("config", "step")
OTHERS = {
    "s7_smart": r"TecoApi|Tecomat|Mosaic|TSAP|rack|slot|ISO-on-TCP|PUT/GET",
    "tecomat": r"S7|SMART|STEP 7|TSAP|rack|slot|ISO-on-TCP|Web API",
    "s7": r"SMART|Web API|TecoApi|Tecomat|certificate|HTTPS|password|log ?in|user",
    "plcnext": r"S7|SMART|STEP 7|TSAP|rack|slot|ISO-on-TCP|TecoApi|Tecomat|Mosaic|Web API",
    "softplc": r"S7|SMART|STEP 7|TecoApi|Tecomat|Mosaic|TSAP|rack|slot|ISO-on-TCP|Web API|"
    r"password|user",
    "logo": r"SMART|Web API|TecoApi|Tecomat|Mosaic|certificate|HTTPS|password|log ?in|user|"
    r"rack|slot",
}
"""Words of other families (or of what the vendor does not have) that its pages must not use."""


def pages(vendor: str) -> dict[str, set[str]]:
    """Return every config-flow page of a vendor: step id -> the fields it shows."""
    client = client_class(vendor)
    found = {
        connection_step(vendor, reconfigure=reconfigure): {
            str(marker)
            for marker in connection_schema(client, vendor, credentials=not reconfigure).schema
        }
        for reconfigure in (False, True)
    }
    if vendor in SECOND_PAGES:
        for way in SECOND_PAGES[vendor].ways:
            step_id, fields = second_page(vendor, {SECOND_PAGES[vendor].choice: way})
            found[step_id] = {str(marker) for marker in fields_schema(fields)}
    return found


def texts(step: dict[str, object]) -> str:
    """Return a step's title, description and help texts as one text."""
    helps = step.get("data_description", {})
    assert isinstance(helps, dict)
    return " ".join([str(step["title"]), str(step["description"]), *map(str, helps.values())])


@pytest.mark.parametrize("vendor", implemented())
def test_every_page_worded_for_its_fields(vendor: str) -> None:
    """Each page has its own title and description, a label and help for each field it shows."""
    for step_id, fields in pages(vendor).items():
        step = strings_at(*STEPS, step_id)
        assert step["title"]
        assert step["description"]
        assert set(step["data"]) == fields, step_id
        assert set(step["data_description"]) == fields, step_id
        assert hasattr(PlcBridgeConfigFlow, f"async_step_{step_id}"), step_id


async def test_vendor_pages_shown_again_without_input(hass: HomeAssistant) -> None:
    """A vendor page's step called without input shows that page again (nothing is checked)."""
    flow = PlcBridgeConfigFlow()
    flow.hass, flow.handler, flow.flow_id = hass, DOMAIN, "pages"
    flow.context = {"source": SOURCE_USER}
    await flow.async_step_vendor({CONF_VENDOR: "s7"})
    assert (await flow.async_step_connection_s7())["step_id"] == "connection_s7"
    result = await flow.async_step_connection_s7(
        {CONF_HOST: "plc", CONF_PORT: 102, "connection": "tsap"}
    )
    assert result["step_id"] == "s7_tsap"
    assert (await flow.async_step_s7_tsap())["step_id"] == "s7_tsap"


@pytest.mark.parametrize("vendor", implemented())
def test_pages_name_no_other_family(vendor: str) -> None:
    """A vendor's pages carry none of another family's words, nor words of what it lacks."""
    for step_id in pages(vendor):
        found = re.findall(OTHERS[vendor], texts(strings_at(*STEPS, step_id)), re.IGNORECASE)
        assert not found, f"{step_id}: {found}"


def test_second_pages_ask_only_their_way() -> None:
    """Rack and slot, or the TSAPs: each page words only its own way."""
    rack_slot = texts(strings_at(*STEPS, "s7_rack_slot"))
    tsap = texts(strings_at(*STEPS, "s7_tsap"))
    assert "TSAP" not in rack_slot
    assert not re.search(r"rack|slot", tsap, re.IGNORECASE)


def test_shared_texts_name_no_family() -> None:
    """Texts every vendor's forms share (TLS choices, errors, reauth) name no family."""
    shared = [
        *strings_at("selector", "tls", "options").values(),
        *strings_at("config", "error").values(),
        texts(strings_at(*STEPS, "reauth_confirm")),
        texts(strings_at(*STEPS, "certificate") | {"data_description": {}}),
    ]
    for text in shared:
        assert not re.search(r"S7|SMART|Tecomat|TecoApi|TSAP", text), text


def test_unknown_way_falls_back_to_the_first() -> None:
    """Options from an older entry without the choice open the first way's page."""
    assert second_page("s7", {})[0] == "s7_rack_slot"
    assert second_page("tecomat", {}) == ("", ())
