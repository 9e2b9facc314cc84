"""REAL values show as the 32-bit floats they are (22.3, not 22.299999237060547): issue 23.

Read alone, in an array read whole, and as a write's read-back, for each way the PLC prints a
REAL (READINGS.md row 5).
"""

from __future__ import annotations

import pytest

from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient
from simulators.tecomat import TecomatSimulator
from simulators.tecomat.values import REAL_FORMATS, WHOLE_ARRAYS

REAL = Point("plcData.varReal", "REAL")
ELEMENTS = [Point(f"arr2[{row}][{column}]", "REAL") for row, column in ((1, 1), (2, 3), (0, 2))]


@pytest.mark.parametrize("whole_arrays", WHOLE_ARRAYS)
@pytest.mark.parametrize("real_format", REAL_FORMATS)
async def test_reals_read_and_written_show_their_shortest_decimal(
    tecomat_sim: TecomatSimulator,
    tecomat_client: TecomatClient,
    real_format: str,
    whole_arrays: str,
) -> None:
    """22.3 written reads back and reads as 22.3; arr2 (read whole) shows 1.1, 2.3, 0.2."""
    tecomat_sim.real_format, tecomat_sim.whole_arrays = real_format, whole_arrays
    written = await tecomat_client.write({REAL: 22.3})
    assert written[REAL].value == 22.3
    assert tecomat_sim.get("plcData.varReal") != 22.3  # the PLC holds the 32-bit float
    for _ in range(2):  # the first poll confirms arr2 starts at 0, the second reads it whole
        result = await tecomat_client.read([REAL, *ELEMENTS])
        values = [result.values[point].value for point in (REAL, *ELEMENTS)]
        assert [repr(value) for value in values] == ["22.3", "1.1", "2.3", "0.2"]
    assert any(
        uri.endswith(("?arr2&plcData.varReal", "?plcData.varReal&arr2")) for uri in tecomat_sim.uris
    )
