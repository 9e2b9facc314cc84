"""TecoApi poll cost: a poll's points parsed once, only the values that changed decoded."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from hypothesis import given, settings, strategies as st
import pytest

from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient, arrays, reading
from custom_components.plc_bridge.plc.vendors.tecomat.paths import parse_path
from simulators.tecomat import TecomatSimulator

if TYPE_CHECKING:
    from .tecomat_fixtures import ConfigFactory


async def test_a_repeated_value_is_not_decoded_again(
    tecomat_config: ConfigFactory, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Of 1,000 points polled again, only the one whose value changed is decoded; the results
    of the others are the last poll's, under their own points. Names spelled as asked are
    found without the general walk of the answer.

    Before: every poll decoded every value and made every result again, looked each point's
    parsed path up by the point (three hashes of each point a poll), and walked every answer
    name by name with the array rules.
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
        monkeypatch.setattr(arrays, "_place", lambda *args, **kw: pytest.fail("walked"))
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


NAMES = st.sampled_from(["a", "A", "b", "c"])
ANSWERS = st.recursive(
    st.none() | st.integers(min_value=0, max_value=3) | st.text(max_size=2),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(NAMES, inner, max_size=3),
    max_leaves=12,
)


@settings(max_examples=300, deadline=None, derandomize=True, database=None)
@given(
    answer=ANSWERS,
    asked=st.lists(
        st.lists(NAMES, min_size=1, max_size=3).map(".".join)
        | st.sampled_from(["a[0]", "b[1].c", "a.b[0]"]),
        max_size=5,
    ),
)
def test_names_found_as_spelled_are_placed_as_the_general_walk_places_them(
    answer: Any, asked: list[str]
) -> None:
    """Paths of names found spelled exactly so take a shorter way, to the same values."""
    paths = list({path.key: path for path in map(parse_path, asked)}.values())
    general: dict[str, Any] = {}
    walk = [(path, 0) for path in paths]
    arrays._place(answer, walk, arrays._Places(general, {}, {}), whole=False)
    assert arrays.answered(answer, paths) == general
