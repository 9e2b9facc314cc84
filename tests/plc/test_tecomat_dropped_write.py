"""A write the PLC answered but did not take fails, instead of reporting success (issue 10)."""

from __future__ import annotations

import pytest

from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient
from simulators.tecomat import TecomatSimulator

REAL = Point("plcData.varReal", "REAL")


@pytest.mark.parametrize("dropped", [False, True], ids=["taken", "dropped"])
async def test_write_read_back(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient, dropped: bool
) -> None:
    """204 proves nothing: the value is read back, and one the PLC does not hold fails."""
    tecomat_sim.drop_writes = dropped
    result = (await tecomat_client.write({REAL: 22.3}))[REAL]
    assert result.ok is not dropped
    if dropped:
        assert "holds 1000.0, not 22.3" in str(result.error)
    else:
        assert tecomat_sim.get("plcData.varReal") == pytest.approx(22.3)
