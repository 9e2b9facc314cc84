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
from tests.expose_fixtures import VENDORS, VendorCase, burst
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
    entry, cost = await burst(hass, freezer, vendor, sim)
    client = entry.runtime_data.client
    result = {
        "check": "expose_burst",
        "vendor": vendor.vendor,
        "exposes": len(cost.sent),
        "write_requests": cost.writes,
        "requests": cost.requests,
        "minimum": client.planned_requests([Point(*target) for target in vendor.burst]),
        "written": sum(held == sent for held, sent in zip(cost.held, cost.sent, strict=True)),
    }
    print("\nBENCH " + json.dumps(result))
    assert result["written"] == len(cost.sent)
    assert result["write_requests"] == result["minimum"]
