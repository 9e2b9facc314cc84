"""PLCnext REAL values travel as the double expansion of their single (22.299999237060547):
read and written, they show as typed (22.3). Row 13 of simulators/plcnext/READINGS.md (numbers
or text) and both error modes of `plcnext_sim`."""

from __future__ import annotations

import pytest

from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors.plcnext import PlcnextClient
from simulators.plcnext import PlcnextSimulator

SETPOINT = Point("MainInstance.Setpoint", "REAL")


@pytest.mark.parametrize("text", [False, True], ids=["numbers", "text"])
async def test_real_shows_22_3(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient, text: bool
) -> None:
    """22.3 written and read back shows 22.3, never 22.299999237060547 (the PLC's JSON)."""
    plcnext_sim.text_values = text
    result = await plcnext_client.write({SETPOINT: 22.3})
    assert result[SETPOINT].value == 22.3
    assert plcnext_sim.var("MainInstance.Setpoint").json(text) in (
        22.299999237060547,
        "22.299999237060547",
    )
    values = (await plcnext_client.read([SETPOINT], poll=False)).values
    assert values[SETPOINT].value == 22.3
