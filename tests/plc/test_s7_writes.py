"""S7 writes against the simulator: STRING lengths as the PLC declares them, refused P inputs,
and S7-200 timers and counters (the simulator's extensions: python-snap7's server has no S7-200
areas and writes one item per request)."""

from __future__ import annotations

import pytest

from custom_components.plc_bridge.plc import PlcAddressError, PlcValueError, Point, Value
from custom_components.plc_bridge.plc.vendors.s7 import S7Client
from simulators.s7 import S7Simulator

from . import s7_fixtures
from .s7_fixtures import ConfigFactory

s7_sim = s7_fixtures.s7_sim
s7_config = s7_fixtures.s7_config
s7_client = s7_fixtures.s7_client

TEXT = Point("DB1.DBB0", "STRING")  # declared STRING[4] in the PLC (header 04 ..)
WORD = Point("DB1.DBW6", "WORD")  # the variable right after it


@pytest.fixture
def string_then_word(s7_sim: S7Simulator) -> S7Simulator:
    """DB1 holds a STRING[4] "ab" at byte 0, then a WORD 0x1234 at byte 6."""
    s7_sim.set_db(1, 0, b"\x04\x02ab\x00\x00\x12\x34")
    return s7_sim


@pytest.mark.parametrize("point", [TEXT, Point("DB1.DBB0", "STRING[10]")])
async def test_string_longer_than_the_plc_declares(
    string_then_word: S7Simulator, s7_client: S7Client, point: Point
) -> None:
    sim = string_then_word
    before = dict(sim.calls)
    results = await s7_client.write({point: "hello"})
    error = results[point].error
    assert isinstance(error, PlcValueError)
    assert "DB1.DBB0 is a STRING[4] in the PLC" in str(error)
    assert sim.get_db(1, 0, 8) == b"\x04\x02ab\x00\x00\x12\x34"  # the word is intact
    assert sim.calls["read"] == before.get("read", 0) + 1  # the header
    assert sim.calls["write"] == before.get("write", 0)  # nothing to write


async def test_string_within_the_plc_length(
    string_then_word: S7Simulator, s7_client: S7Client
) -> None:
    sim = string_then_word
    results = await s7_client.write({TEXT: "wxyz", WORD: 0xBEEF, Point("MW0", "INT"): 5})
    assert all(result.ok for result in results.values())
    assert sim.get_db(1, 0, 8) == b"\x04\x04wxyz\xbe\xef"  # maximum length byte left alone
    assert (await s7_client.read([TEXT])).values[TEXT].value == "wxyz"


async def test_string_headers_read_in_one_request(s7_sim: S7Simulator, s7_client: S7Client) -> None:
    s7_sim.set_db(1, 100, b"\x06\x00")
    s7_sim.set_db(2, 10, b"\x02\x00")
    values: dict[Point, Value] = {
        Point("DB1.DBB100", "STRING"): "sixsix",
        Point("DB2.DBB10", "STRING[10]"): "toolong",  # the PLC says STRING[2]
        Point("DB1.DBB200", "STRING[8]"): "x",  # never initialized: zeros, no STRING there
        Point("DB9.DBB0", "STRING"): "x",  # no DB9
        Point("MW2", "INT"): 1,
    }
    before = dict(s7_sim.calls)
    results = await s7_client.write(values)
    # One read of every header, and DB9's asked again once (it ends the job: simulators/s7/
    # READINGS.md, items past a CPU's limit).
    assert s7_sim.calls["read"] == before.get("read", 0) + 2
    assert s7_sim.calls["write"] == before.get("write", 0) + 1
    assert results[Point("DB1.DBB100", "STRING")].ok
    assert s7_sim.get_db(1, 100, 8) == b"\x06\x06sixsix"
    assert "STRING[2] in the PLC" in str(results[Point("DB2.DBB10", "STRING[10]")].error)
    unset = results[Point("DB1.DBB200", "STRING[8]")].error
    assert isinstance(unset, PlcAddressError)
    assert "holds no S7 STRING: its header reads 00 00" in str(unset)
    assert "no such object" in str(results[Point("DB9.DBB0", "STRING")].error)
    assert results[Point("MW2", "INT")].ok


async def test_peripheral_inputs_are_refused(s7_sim: S7Simulator, s7_client: S7Client) -> None:
    s7_sim.set_bytes("Q", 0, b"\x11\x22")
    requests = s7_sim.requests
    with pytest.raises(PlcValueError, match="PIW0: peripheral inputs cannot be written"):
        await s7_client.write({Point("PIW0", "WORD"): 1})
    with pytest.raises(PlcValueError, match="peripheral inputs"):
        S7Client.validate_value(Point("PIB3", "BYTE"), 1)
    assert s7_sim.requests == requests  # nothing sent
    assert s7_sim.get_bytes("Q", 0, 2) == b"\x11\x22"  # the outputs at the same address
    assert (await s7_client.write({Point("PQW0", "WORD"): 7}))[Point("PQW0", "WORD")].ok


S7_200 = {"connection": "tsap", "local_tsap": "10.00", "remote_tsap": "10.01"}
TIMERS = {Point("T5", "WORD"): 0x2123, Point("C3", "WORD"): 0x0042, Point("T6", "WORD"): 7}


@pytest.mark.parametrize(
    ("sim_family", "client_family", "works"),
    [
        ("s7_200", "s7_200", True),
        ("s7_200", "s7_300_1500", False),  # 0x1D/0x1C: an S7-200 has no such objects
        ("s7_300_1500", "s7_200", False),  # 0x1F/0x1E: an S7-300 has none of these
    ],
)
async def test_s7_200_timers_and_counters(
    s7_config: ConfigFactory, sim_family: str, client_family: str, works: bool
) -> None:
    sim = S7Simulator(remote_tsap=0x1001, szl=False, family=sim_family)
    await sim.start()
    client = S7Client(s7_config(port=sim.port, options=S7_200 | {"family": client_family}))
    try:
        await client.connect()
        sim.set_bytes("C", 3, b"\x00\x99")
        written = await client.write(TIMERS)
        read = (await client.read(list(TIMERS))).values
        if works:
            assert all(result.ok for result in written.values())
            assert {point: result.value for point, result in read.items()} == TIMERS
            assert sim.get_bytes("T", 5, 4) == b"\x21\x23\x00\x07"
            assert sim.get_bytes("C", 3, 2) == b"\x00\x42"
        else:
            for outcome in (*written.values(), *read.values()):
                assert "no such object" in str(outcome.error)
            assert sim.get_bytes("C", 3, 2) == b"\x00\x99"
    finally:
        await client.close()
        await sim.stop()
