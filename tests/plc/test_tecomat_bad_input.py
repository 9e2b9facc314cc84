"""Bad values and hostile answers end in the project's own errors (issue 19)."""

from __future__ import annotations

import pytest

from custom_components.plc_bridge.plc import PlcProtocolError, PlcValueError, Point
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient
from custom_components.plc_bridge.plc.vendors.tecomat.errors import parse_error
from simulators.tecomat import TecomatSimulator

DEEP = b"[" * 200_000 + b"]" * 200_000
"""Nested deeper than the JSON decoder's stack: it raises RecursionError, not ValueError."""


@pytest.mark.parametrize("kind", ["TIME", "TOD"])
@pytest.mark.parametrize(
    "value",
    [10**400, 10**5000, -(10**400), 1e308, -1e308],
    ids=["10**400", "10**5000", "-10**400", "1e308", "-1e308"],
)
def test_time_of_any_size(kind: str, value: float) -> None:
    """Before: 10**400 raised OverflowError (math.isfinite), 1e308 too (round of infinity)."""
    with pytest.raises(PlcValueError, match=f"outside the range of a {kind}"):
        TecomatClient.validate_value(Point("plcData.varTime", kind), value)


async def test_deeply_nested_answer(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    """Before: RecursionError escaped, and Home Assistant gave up setup without a retry."""
    tecomat_sim.rewrite = lambda body: DEEP
    with pytest.raises(PlcProtocolError):
        await tecomat_client.connect()
    with pytest.raises(PlcProtocolError):
        await tecomat_client.read([Point("plcName", "STRING")])
    assert parse_error(400, DEEP).code == "400.000"


async def test_deep_but_decodable_answer_while_browsing(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    """A value nested 5,000 deep decodes, but is not walked into: listed as unlisted."""
    deep = b'{"plcDesc":' + b"[" * 5000 + b"]" * 5000 + b"}"
    tecomat_sim.rewrite = lambda body: deep if b'"plcDesc"' in body else body
    await tecomat_client.browse()
    assert "plcDesc" in tecomat_client.unlisted
