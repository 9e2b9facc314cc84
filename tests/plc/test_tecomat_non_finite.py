"""A REAL the PLC prints as nan or inf (not JSON) fails its own point, not the poll (issue 10)."""

from __future__ import annotations

import pytest

from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient
from custom_components.plc_bridge.plc.vendors.tecomat.api import loads
from simulators.tecomat import TecomatSimulator

REAL = Point("plcData.varReal", "REAL")
TEXT = Point("plcData.varString", "STRING")


@pytest.mark.parametrize("printed", [float("nan"), float("inf"), float("-inf")])
async def test_non_finite_real_fails_alone(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient, printed: float
) -> None:
    """The simulator prints the REAL as C does ("nan", "inf"); the string beside it still reads."""
    tecomat_sim.set("plcData.varReal", printed)
    tecomat_sim.set("plcData.varString", "nan, inf and -inf stay text")
    result = await tecomat_client.read([REAL, TEXT])
    assert not result.values[REAL].ok
    assert result.values[TEXT].value == "nan, inf and -inf stay text"


def test_words_inside_strings_untouched() -> None:
    """Only bare words are replaced: a string that says nan is kept as it is."""
    text = r'{"a": nan, "b": "x: nan", "c": [inf, -inf, 1.5], "d": "say \"nan\""}'
    assert loads(text) == {"a": None, "b": "x: nan", "c": [None, None, 1.5], "d": 'say "nan"'}
