"""A LOGO! of each generation: identity, blocks and VM read in one request, writes it allows."""

from __future__ import annotations

import pytest

from custom_components.plc_bridge.plc import (
    PlcSessionRefusedError,
    PlcValueError,
    PlcWriteRefusedError,
    Point,
)
from custom_components.plc_bridge.plc.vendors.logo import LogoClient
from simulators.logo import LogoSimulator
from tests.loopback import ConfigFactory, connected

from .logo_fixtures import logo_client, logo_config, logo_sim

__all__ = ["logo_client", "logo_config", "logo_sim"]

BOTH = [
    Point("I1", "BOOL"),
    Point("I10", "BOOL"),
    Point("Q2", "BOOL"),
    Point("M9", "BOOL"),
    Point("AI1", "INT"),
    Point("AQ2", "INT"),
    Point("AM3", "INT"),
    Point("V10.3", "BOOL"),
    Point("VW20", "INT"),
]
NETWORK = [Point("NI5", "BOOL"), Point("NAI2", "INT")]


def points_of(sim: LogoSimulator) -> list[Point]:
    """The points a LOGO! of the simulator's generation has."""
    return BOTH + (NETWORK if sim.generation != "0ba7" else [])


async def test_named_by_generation(logo_sim: LogoSimulator, logo_client: LogoClient) -> None:
    """No SZL list answers: the model is the generation's name; the session has PDU 240."""
    info = await logo_client.connect()
    assert info.vendor == "logo"
    assert info.model.startswith("LOGO! ")
    assert info.extra["generation"] == logo_sim.generation
    assert logo_client.pdu_size == 240


async def test_inputs_outputs_flags_analog_in_one_read(
    logo_sim: LogoSimulator, logo_client: LogoClient
) -> None:
    """I, Q, M, AI, AQ, AM (and network inputs) and VM come in one read request."""
    logo_sim.set_block("I10", True)
    logo_sim.set_block("Q2", True)
    logo_sim.set_block("M9", True)
    logo_sim.set_block("AI1", 512)
    logo_sim.set_block("AQ2", -7)
    logo_sim.set_block("AM3", 1000)
    logo_sim.set_bytes("DB", 10, b"\x08", db=1)
    logo_sim.set_bytes("DB", 20, (-300).to_bytes(2, "big", signed=True), db=1)
    if logo_sim.generation != "0ba7":
        logo_sim.set_block("NI5", True)
        logo_sim.set_block("NAI2", 42)
    points = points_of(logo_sim)
    await logo_client.read(points)  # the first poll asks the status too: not counted here
    before = logo_sim.calls["read"]
    result = await logo_client.read(points)
    assert logo_sim.calls["read"] - before == 1
    values = {point.address: result.values[point].value for point in points}
    assert values == {
        "I1": False,
        "I10": True,
        "Q2": True,
        "M9": True,
        "AI1": 512,
        "AQ2": -7,
        "AM3": 1000,
        "V10.3": True,
        "VW20": -300,
    } | ({"NI5": True, "NAI2": 42} if logo_sim.generation != "0ba7" else {})
    assert logo_client.planned_requests(points) == 1


async def test_a_block_the_generation_lacks_fails_alone(
    logo_sim: LogoSimulator, logo_client: LogoClient
) -> None:
    """Q17 on a 0BA7 (Q1..Q16), NI1 on a 0BA7: their points fail, the others read."""
    if logo_sim.generation != "0ba7":
        pytest.skip("a LOGO! 8 has Q17 and NI1")
    points = [Point("Q17", "BOOL"), Point("NI1", "BOOL"), Point("Q16", "BOOL")]
    result = await logo_client.read(points)
    assert "Q1 to Q16" in str(result.values[points[0]].error)
    assert "has none" in str(result.values[points[1]].error)
    assert result.values[points[2]].ok


async def test_network_input_written_and_read_back(
    logo_sim: LogoSimulator, logo_client: LogoClient
) -> None:
    """NI and NAI are written (and read back by the client); so is VM."""
    if logo_sim.generation == "0ba7":
        pytest.skip("a 0BA7 has no network inputs")
    values = {Point("NI5", "BOOL"): True, Point("NAI2", "INT"): -1234, Point("VW20", "INT"): 7}
    results = await logo_client.write(values)
    assert all(result.ok for result in results.values()), results
    assert logo_sim.get_block("NI5") is True
    assert logo_sim.get_block("NAI2") == -1234
    read = await logo_client.read(list(values), poll=False)
    assert {point: read.values[point].value for point in values} == values


async def test_a_network_input_the_program_rewrites_fails(
    logo_sim: LogoSimulator, logo_client: LogoClient
) -> None:
    """A LOGO! whose NI block takes its value elsewhere loses the write: the point fails."""
    if logo_sim.generation == "0ba7":
        pytest.skip("a 0BA7 has no network inputs")
    logo_sim.network_inputs = "rewritten"
    logo_sim.set_block("NI5", False, by_program=True)
    results = await logo_client.write({Point("NI5", "BOOL"): True, Point("V0.0", "BOOL"): True})
    assert isinstance(results[Point("NI5", "BOOL")].error, PlcWriteRefusedError)
    assert "does not take this network input" in str(results[Point("NI5", "BOOL")].error)
    assert results[Point("V0.0", "BOOL")].ok


@pytest.mark.parametrize("address", ["Q1", "I1", "M1", "NQ1"])
async def test_an_output_write_is_refused_before_sending(
    logo_sim: LogoSimulator, logo_client: LogoClient, address: str
) -> None:
    """Writes to inputs, outputs, flags and network outputs never reach the LOGO!."""
    point = Point(address, "BOOL")
    assert not LogoClient.address_writable(point)
    before = logo_sim.calls["write"]
    with pytest.raises(PlcValueError, match="V memory and network inputs"):
        await logo_client.write({point: True})
    assert logo_sim.calls["write"] == before


async def test_another_tsap_is_refused(logo_sim: LogoSimulator, logo_config: ConfigFactory) -> None:
    """A TSAP the LOGO! has no server connection for: the session is refused."""
    options = {"generation": logo_sim.generation, "remote_tsap": "03.01"}
    with pytest.raises(PlcSessionRefusedError):
        async with connected(LogoClient(logo_config(options=options))):
            pass
    logo_sim.server_tsaps = {0x0301}
    async with connected(LogoClient(logo_config(options=options))) as client:
        assert (await client.read([Point("I1", "BOOL")])).values[Point("I1", "BOOL")].ok
