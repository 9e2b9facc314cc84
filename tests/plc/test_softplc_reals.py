"""SoftPLC REAL values: shown as the single they are, and a write's echo read as printed.

The client-facing tests run against every reading of row 15 of simulators/softplc/READINGS.md
(how a float is printed: `reals`), fixture `softplc_reals`.
"""

from __future__ import annotations

import logging
import struct

import pytest

from custom_components.plc_bridge.plc import PlcProtocolError, PlcWriteRefusedError, Point
from custom_components.plc_bridge.plc.vendors.softplc import SoftplcClient
from custom_components.plc_bridge.plc.vendors.softplc.document import Item
from custom_components.plc_bridge.plc.vendors.softplc.writing import Sent, confirm
from simulators.softplc import SoftplcSimulator

from .softplc_fixtures import softplc_reals

__all__ = ["softplc_reals"]  # a fixture, imported to be found

type Reals = tuple[SoftplcSimulator, SoftplcClient]
WARM, BIG = Point("F8:1", "REAL"), Point("F8:2", "REAL")
LOGGER = "custom_components.plc_bridge.plc.vendors.softplc.client"


def single(value: float) -> float:
    """Return the IEEE single a REAL stores for value."""
    return float(struct.unpack("<f", struct.pack("<f", value))[0])


def unread(caplog: pytest.LogCaptureFixture) -> list[str]:
    """Return the warnings of writes done but not read back."""
    return [r.getMessage() for r in caplog.records if "written, not read back" in r.getMessage()]


async def test_reals_read_as_the_single_they_are(softplc_reals: Reals) -> None:
    """22.3 stored as a single shows 22.3 however printed; digits grouped beside a decimal
    comma ("1.234,567749") cannot be told from two numbers: that point fails alone."""
    sim, client = softplc_reals
    sim.files["F", 8].words[1:3] = [single(22.3), single(1234.5678)]
    values = (await client.read([WARM, BIG, Point("N7:3", "INT")])).values
    assert values[WARM].value == 22.3
    assert values[Point("N7:3", "INT")].value == 3
    if sim.reals == "grouped":
        assert isinstance(values[BIG].error, PlcProtocolError)
    else:
        assert values[BIG].ok


async def test_real_write_echo_read_as_printed(
    softplc_reals: Reals, caplog: pytest.LogCaptureFixture
) -> None:
    """A REAL write is done whatever the echo's print: confirmed where the echo shows the value
    (decimal comma, exponent, more or fewer digits); where it cannot be read or told apart,
    done and logged once as "written, not read back". Before: "22,3" failed the write."""
    sim, client = softplc_reals
    caplog.set_level(logging.WARNING, logger=LOGGER)
    results = await client.write({WARM: 22.3, BIG: 1234.5678})
    assert results[WARM].value == 22.3
    assert results[BIG].value == 1234.5678
    assert sim.files["F", 8].words[1:3] == [single(22.3), single(1234.5678)]
    told = sim.reals not in ("short", "grouped")  # "1235"; "1.234,567749"
    assert [message.partition(" ")[0] for message in unread(caplog)] == ([] if told else ["F8:2"])
    await client.write({WARM: 22.3, BIG: 1234.5678})
    assert len(unread(caplog)) == (0 if told else 1)  # once, not at every write


@pytest.mark.parametrize(
    ("echo", "outcome"),
    [
        ("22.3", "confirmed"),
        ("22,3", "confirmed"),
        ("2.230000e+01", "confirmed"),
        ("2,23e1", "confirmed"),
        ("22.2999992", "confirmed"),
        ("22.299999", "confirmed"),
        ("22.30000", "confirmed"),
        ("22.4", "refused"),
        ("22,4", "refused"),
        ("-22.3", "refused"),
        ("22", "unread"),  # a whole number: 22.3 printed without decimals, or 22 stored
        ("22.3 C", "unread"),
        ("1.022,3", "unread"),
        ("", "unread"),
    ],
)
def test_echo_of_22_3(echo: str, outcome: str) -> None:
    """The echo of a REAL write of 22.3, each way a PLC may print it."""
    sent = Sent(WARM, 22.3, 0, "22.3")
    result, why = confirm(Item("F8:1", 1, (echo,) if echo else ()), sent)
    if outcome == "refused":
        assert isinstance(result.error, PlcWriteRefusedError)
    else:
        assert result.value == 22.3
        assert bool(why) == (outcome == "unread")


def test_integer_echo_unread_is_no_failure() -> None:
    """An integer word's echo that is no number is done, not read back; another number fails."""
    sent = Sent(Point("N7:0", "INT"), 77, 0, "77")
    assert confirm(Item("N7:0", 1, ("busy",)), sent)[0].value == 77
    assert confirm(Item("N7:0", 1, ("busy",)), sent)[1]
    assert confirm(Item("N7:0", 1, ("77,0",)), sent) == (confirm(Item("N7:0", 1, ("77",)), sent))
    assert isinstance(confirm(Item("N7:0", 1, ("78",)), sent)[0].error, PlcWriteRefusedError)
