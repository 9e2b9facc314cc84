"""PLCnext poll cost: a group's answer placed a list at a time, only changed values decoded."""

from __future__ import annotations

import math
from typing import Any

from hypothesis import HealthCheck, given, settings, strategies as st
import pytest

from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.unchanged import changed
from custom_components.plc_bridge.plc.vendors.plcnext import PlcnextClient, placing, results
from custom_components.plc_bridge.plc.vendors.plcnext.paths import parse_path
from custom_components.plc_bridge.plc.vendors.plcnext.placing import Reading, place
from custom_components.plc_bridge.plc.vendors.plcnext.reading import registered
from simulators.plcnext import PlcnextSimulator
from simulators.plcnext.demo import default_program

BOUNDED = settings(
    max_examples=200,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
    derandomize=True,
    database=None,
)
SCALARS = (
    st.none()
    | st.booleans()
    | st.sampled_from([0, 1, -1, 0.0, -0.0, 1.0, math.nan, math.inf, "0", "1", ""])
    | st.integers(min_value=-3, max_value=3)
    | st.floats(min_value=-2, max_value=2)
    | st.lists(st.integers(min_value=0, max_value=1), max_size=2)
)


def same_json(old: Any, new: Any) -> bool:
    """The reference: the same value of the same type, and 0.0 is not -0.0."""
    return old == new and type(old) is type(new) and (bool(new) or type(new) is not float)


@BOUNDED
@given(pairs=st.lists(st.tuples(SCALARS, SCALARS), max_size=12))
def test_changed_is_every_value_not_the_same(pairs: list[tuple[Any, Any]]) -> None:
    """`changed` finds exactly the positions whose value is not the same JSON value as before."""
    last, raws = [old for old, _new in pairs], [new for _old, new in pairs]
    expected = {index for index, (old, new) in enumerate(pairs) if not same_json(old, new)}
    assert changed(raws, last) == expected
    assert changed(raws, None) == set(range(len(raws)))


NAMES = ["Main.a", "Main.b", "Main.c"]
ENTRY = st.fixed_dictionaries(
    {},
    optional={
        "path": st.sampled_from([*NAMES, "Arp.Plc.Eclr/Main.a", "main.B", "Other"]),
        "value": st.integers(min_value=0, max_value=3),
        "error": st.none() | st.just({"reason": "invalidName"}),
        "type": st.just("DINT"),
    },
)


@BOUNDED
@given(entries=st.lists(ENTRY | st.integers(), min_size=3, max_size=3))
def test_registered_names_place_as_the_general_rule(entries: list[Any]) -> None:
    """Checking the names as registered places every answer as matching entry by entry does."""
    paths = [parse_path(name) for name in NAMES]
    fast, general = Reading(), Reading()
    place({"variables": entries}, paths, fast, registered(paths)[1])
    place({"variables": entries}, paths, general)
    assert fast.found == general.found
    assert {key: str(err) for key, err in fast.failed.items()} == {
        key: str(err) for key, err in general.failed.items()
    }


async def test_a_repeated_answer_runs_no_code_per_value(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Polls of 1,000 values match no entry one by one; only a changed value is decoded.

    Before: every poll matched the answer's 1,000 entries to their paths one by one, and
    looked up and compared every value in Python code of its own (at 5,000 variables, 2.3
    times pyPLCn's client CPU).
    """
    plcnext_sim.program = default_program(1000)
    points = [Point(f"Bench.Value{index}", "DINT") for index in range(1000)]
    await plcnext_client.read(points)
    decoded: list[Any] = []
    decode = results.decode

    def counted(kind: str, raw: Any, *args: Any) -> Any:
        """Count the values decoded."""
        decoded.append(raw)
        return decode(kind, raw, *args)

    monkeypatch.setattr(results, "decode", counted)
    monkeypatch.setattr(placing, "in_order", lambda *args: pytest.fail("matched one by one"))
    plcnext_sim.set("Bench.Value7", 70)
    first = await plcnext_client.read(points)
    second = await plcnext_client.read(points)
    assert [first.values[point].value for point in points[5:9]] == [5, 6, 70, 8]
    assert second.values == first.values
    assert second.values is not first.values
    assert [raw for raw in decoded if not isinstance(raw, str)] == [70]  # str: the clock's DT
    assert plcnext_client.metrics.last_poll_requests == 1
