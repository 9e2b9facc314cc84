"""A write the PLC acknowledged stands when its read-back gets no usable answer (issue 23).

Before, a malformed read-back reported a write failed that the PLC had taken (HTTP 204).
"""

from __future__ import annotations

import logging

import pytest

from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient
from simulators.tecomat import TecomatSimulator

AGE, FOOD = Point("myObject.age", "USINT"), Point("myObject.favorites.food", "STRING")
MALFORMED = {
    "not-json": lambda body: b"{" + body,
    "empty-object": lambda body: b"{}",
    "wrong-type": lambda body: body.replace(b"41", b'"forty-one"'),
    "not-an-object": lambda body: b"[1, 2]",
}


@pytest.mark.parametrize("malformed", MALFORMED)
async def test_acknowledged_write_with_a_malformed_read_back(
    tecomat_sim: TecomatSimulator,
    tecomat_client: TecomatClient,
    caplog: pytest.LogCaptureFixture,
    malformed: str,
) -> None:
    """The write is done, its value unshown; one warning names the variable, once."""
    tecomat_sim.rewrite = MALFORMED[malformed]
    with caplog.at_level(logging.DEBUG):
        first = await tecomat_client.write({AGE: 41, FOOD: "Pizza"})
        second = await tecomat_client.write({AGE: 41})
    for results in (first, second):
        assert results[AGE].ok, results[AGE].error
        assert results[AGE].value is None  # not read back: the next poll shows it
    assert first[FOOD].ok
    assert tecomat_sim.get("myObject.age") == 41
    assert tecomat_sim.get("myObject.favorites.food") == "Pizza"
    warnings = [r.getMessage() for r in caplog.records if r.levelno == logging.WARNING]
    age = [text for text in warnings if text.startswith("myObject.age: written, not read back")]
    assert len(age) == 1, warnings
    tecomat_sim.rewrite = None
    assert (await tecomat_client.read([AGE])).values[AGE].value == 41


async def test_a_dropped_write_still_fails_with_a_malformed_neighbour(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    """A read-back that shows another value still fails the write (READINGS.md row 13)."""
    tecomat_sim.drop_writes = True
    results = await tecomat_client.write({AGE: 41})
    assert "holds 39, not 41" in str(results[AGE].error)
