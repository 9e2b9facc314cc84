"""A machine of the richer kinds costs no request beyond its addresses' plan: in Home Assistant.

Run by `scripts/bench` (pytest with the test suite's fixtures): one machine on the S7-200 SMART
simulator holding a climate, a cover, a select and an alarm word. Each poll's requests, counted
at the simulator, are compared with the client's plan for the same addresses as bare points.
"""

from __future__ import annotations

import json

from freezegun.api import FrozenDateTimeFactory
from homeassistant.core import HomeAssistant

from simulators.s7_smart import S7SmartSimulator
from tests.entries import make_entry, point, poll

POLLS = 3
KINDS = "a climate, a cover, a select and an alarm word"
MACHINE = [
    point("c1", "Boiler", "climate", "VW50", "signed", role="current_temperature", read_only=True),
    point(
        "c2", "Boiler", "climate", "VW52", "signed", role="target_temperature", min=5.0, max=30.0
    ),
    point("c3", "Boiler", "climate", "VW54", "signed", role="hvac_mode", value_map="0=off;1=heat"),
    point("s1", "Shutter", "cover", "Q0.4", "signed", role="open"),
    point("s2", "Shutter", "cover", "Q0.5", "signed", role="close"),
    point("s3", "Shutter", "cover", "I0.1", "signed", role="open_limit", read_only=True),
    point("s4", "Shutter", "cover", "I0.2", "signed", role="closed_limit", read_only=True),
    point("mode", "Mode", "select", "VW30", "signed", value_map="0=Off;1=Auto;2=Manual"),
    point("alarms", "Alarms", "event", "VW70", "signed", bits="0=Overheat;3=Low water"),
]


async def test_machine_kinds(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """Poll the machine a few times; its requests per poll equal the plan of its addresses."""
    for address, value in (("VW50", 215), ("VW52", 220), ("VW54", 1), ("VW30", 1), ("VW70", 0)):
        s7_smart_ha_sim.set(address, value)
    entry = make_entry(hass, s7_smart_ha_sim, MACHINE)
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    await poll(hass, freezer)  # the first poll after setup may still fill in values
    per_poll: list[int] = []
    for _ in range(POLLS):
        before = s7_smart_ha_sim.requests
        await poll(hass, freezer)
        per_poll.append(s7_smart_ha_sim.requests - before)
    runtime = entry.runtime_data
    values = runtime.coordinator.data.values
    result = {
        "check": "machine_kinds",
        "vendor": "s7_smart",
        "kinds": KINDS,
        "addresses": len(values),
        "polls": POLLS,
        "requests_per_poll": max(per_poll),
        "planned_requests": runtime.client.planned_requests(list(values)),
        "failed_points": sum(1 for result in values.values() if not result.ok),
    }
    print("\nBENCH " + json.dumps(result))
    assert result["addresses"] == len(MACHINE)
    assert result["requests_per_poll"] == result["planned_requests"]
