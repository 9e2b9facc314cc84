"""Exposes changed at once cost the vendor's fewest write requests: in Home Assistant.

Run by `scripts/bench` (pytest with the test suite's fixtures): on each vendor's simulator, ten
exposes whose entities change in the same moment (and forty on the S7-200 SMART). The write
requests the simulator serves are compared with the client's plan for the same addresses (the
fewest requests the vendor allows).
"""

from __future__ import annotations

from collections.abc import AsyncGenerator
from dataclasses import replace
import json

from freezegun.api import FrozenDateTimeFactory
from homeassistant.core import HomeAssistant
import pytest

from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors import client_class, implemented
from tests.harness import FAMILIES, PlcUnderTest, burst, started


@pytest.fixture(autouse=True)
def no_vendor_pacing(monkeypatch: pytest.MonkeyPatch) -> None:
    """No vendor paces its requests: the figures are the protocol's cost."""
    for vendor in implemented():
        monkeypatch.setattr(client_class(vendor), "request_interval", 0.0)


FORTY = [(f"VW{600 + 2 * i}", "signed") for i in range(40)]
"""Forty exposes on the S7-200 SMART: more than one request's 32 nodes."""


@pytest.fixture(params=[*FAMILIES, "s7_smart-40"])
async def every_plc(
    request: pytest.FixtureRequest, hass: HomeAssistant, freezer: FrozenDateTimeFactory
) -> AsyncGenerator[PlcUnderTest]:
    """Each family's PLC with its ten exposes, and an S7-200 SMART with forty."""
    key, _, forty = request.param.partition("-")
    async with started(hass, key) as plc:
        yield replace(plc, family=replace(plc.family, burst=FORTY)) if forty else plc


async def test_expose_burst(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, every_plc: PlcUnderTest
) -> None:
    """Change every exposed entity at once; count the write requests the PLC serves."""
    plc = every_plc
    entry, cost = await burst(hass, freezer, plc)
    client = entry.runtime_data.client
    result = {
        "check": "expose_burst",
        "vendor": plc.vendor,
        "exposes": len(cost.sent),
        "write_requests": cost.writes,
        "requests": cost.requests,
        "minimum": client.planned_requests([Point(*target) for target in plc.family.burst]),
        "written": sum(held == sent for held, sent in zip(cost.held, cost.sent, strict=True)),
    }
    print("\nBENCH " + json.dumps(result))
    assert result["written"] == len(cost.sent)
    assert result["write_requests"] == result["minimum"]
