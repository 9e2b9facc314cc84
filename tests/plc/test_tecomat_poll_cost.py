"""TecoApi poll cost: a poll's points parsed once, only the values that changed decoded."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import pytest

from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient, reading
from simulators.tecomat import TecomatSimulator

if TYPE_CHECKING:
    from .tecomat_fixtures import ConfigFactory


async def test_a_repeated_value_is_not_decoded_again(
    tecomat_config: ConfigFactory, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Of 1,000 points polled again, only the one whose value changed is decoded; the results
    of the others are the last poll's, under their own points.

    Before: every poll decoded every value and made every result again, and looked each
    point's parsed path up by the point (three hashes of each point a poll).
    """
    sim = TecomatSimulator(bench=1000)
    await sim.start()
    client = TecomatClient(tecomat_config(port=sim.port))
    points = [Point(f"BENCH.V{index}", "INT") for index in range(1000)]
    decoded: list[Any] = []
    decode = reading.decode

    def counted(kind: str, raw: Any, *args: Any) -> Any:
        """Count the values decoded."""
        decoded.append(raw)
        return decode(kind, raw, *args)

    try:
        await client.connect()
        first = await client.read(points)
        monkeypatch.setattr(reading, "decode", counted)
        sim.set("BENCH.V7", 70)
        second = await client.read(points)
        third = await client.read(points)
    finally:
        await client.close()
        await sim.stop()
    assert decoded == [70]
    assert [second.values[point].value for point in points[5:9]] == [5, 6, 70, 8]
    assert third.values == second.values
    assert {p: r for p, r in second.values.items() if p != points[7]} == {
        p: r for p, r in first.values.items() if p != points[7]
    }
