"""A write the PLC answered but did not take fails; one it took, printed rounded, does not."""

from __future__ import annotations

import pytest

from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient
from simulators.tecomat import TecomatSimulator
from simulators.tecomat.values import REAL_FORMATS

REAL = Point("plcData.varReal", "REAL")
LREAL = Point("plcData.varLreal", "LREAL")


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


@pytest.mark.parametrize("real_format", REAL_FORMATS)
@pytest.mark.parametrize(
    ("point", "value"),
    [
        (REAL, 1e-07),
        (REAL, 1234567.123456789),
        (REAL, -3.4e38),
        (LREAL, 1e-07),
        (LREAL, 1234567.123456789),
        (LREAL, 0.1234565),
    ],
)
async def test_written_real_printed_rounded(
    tecomat_sim: TecomatSimulator,
    tecomat_client: TecomatClient,
    real_format: str,
    point: Point,
    value: float,
) -> None:
    """The PLC prints six decimals (1e-07 reads back as 0.000000): still taken (issue 19).

    Before: reported "the PLC answered the write but holds 0.0, not 1e-07".
    """
    tecomat_sim.real_format = real_format
    result = (await tecomat_client.write({point: value}))[point]
    assert result.ok, result.error
    assert tecomat_sim.get(point.address) == pytest.approx(value, rel=1e-7)


@pytest.mark.parametrize("real_format", REAL_FORMATS)
async def test_a_dropped_real_still_fails(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient, real_format: str
) -> None:
    """A value the PLC does not hold fails in either print form: 0.000002 is not 0.000001."""
    tecomat_sim.real_format = real_format
    tecomat_sim.set(LREAL.address, 2e-6)
    tecomat_sim.drop_writes = True
    assert not (await tecomat_client.write({LREAL: 1e-6}))[LREAL].ok
