"""Exposes changed at once cost the vendor's fewest write requests: in Home Assistant.

Run by `scripts/bench` (pytest with the test suite's fixtures): on each vendor's simulator, ten
exposes whose entities change in the same moment (and forty on the S7-200 SMART). The write
requests the simulator serves are compared with the client's plan for the same addresses (the
fewest requests the vendor allows).
"""

from __future__ import annotations

from dataclasses import replace
import json
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.core import HomeAssistant
import pytest

from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors import client_class, implemented
from tests.expose_fixtures import VENDORS, VendorCase, add_expose, settle, shown
from tests.ha_fixtures import set_up
from tests.plcnext_ha_fixtures import plcnext_sim  # noqa: F401  (fixtures by name)
from tests.s7_ha_fixtures import s7_ha_sim, s7_ha_sims  # noqa: F401
from tests.softplc_ha_fixtures import softplc_sim  # noqa: F401
from tests.tecomat_ha_fixtures import tecomat_sim  # noqa: F401


@pytest.fixture(autouse=True)
def no_vendor_pacing(monkeypatch: pytest.MonkeyPatch) -> None:
    """No vendor paces its requests: the figures are the protocol's cost."""
    for vendor in implemented():
        monkeypatch.setattr(client_class(vendor), "request_interval", 0.0)


SMART_40 = replace(VENDORS[0], burst=[(f"VW{600 + 2 * i}", "signed") for i in range(40)])
"""Forty exposes on the S7-200 SMART: more than one request's 32 nodes."""


@pytest.fixture(params=[*VENDORS, SMART_40], ids=lambda case: f"{case.vendor}-{len(case.burst)}")
def case(request: pytest.FixtureRequest) -> tuple[VendorCase, Any]:
    """Each vendor, with its simulator started (time frozen until its entries are unloaded)."""
    vendor: VendorCase = request.param
    return vendor, request.getfixturevalue(vendor.sim)


async def test_expose_burst(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, case: tuple[VendorCase, Any]
) -> None:
    """Change every exposed entity at once; count the write requests the PLC serves."""
    vendor, sim = case
    entities = [f"input_number.level_{index}" for index in range(len(vendor.burst))]
    for entity_id in entities:
        hass.states.async_set(entity_id, "0")
    entry = vendor.entry(hass, sim, [shown(vendor)])
    for entity_id, target in zip(entities, vendor.burst, strict=True):
        add_expose(hass, entry, entity_id, target)
    await set_up(hass, entry)
    client = entry.runtime_data.client
    writes, requests = vendor.writes(sim), client.metrics.requests
    for index, entity_id in enumerate(entities):
        hass.states.async_set(entity_id, str(index % 100 + 11))
    await settle(hass, freezer)
    result = {
        "check": "expose_burst",
        "vendor": vendor.vendor,
        "exposes": len(entities),
        "write_requests": vendor.writes(sim) - writes,
        "requests": client.metrics.requests - requests,
        "minimum": client.planned_requests([Point(*target) for target in vendor.burst]),
        "written": sum(
            vendor.read(sim, *target) == index % 100 + 11
            for index, target in enumerate(vendor.burst)
        ),
    }
    print("\nBENCH " + json.dumps(result))
    assert result["written"] == len(entities)
    assert result["write_requests"] == result["minimum"]
