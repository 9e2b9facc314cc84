"""The S7-200 SMART client under each reading of what its manual leaves open (READINGS.md).

Node limits refused in every way a firmware might, HTTP answers from a busy web server, replies
nested too deep to parse, node refusals in a firmware's own codes and words.
"""

from __future__ import annotations

import pytest

from custom_components.plc_bridge.plc import (
    PlcAddressError,
    PlcConnectionError,
    PlcProtocolError,
    PlcWriteRefusedError,
    Point,
)
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient, rpc
from custom_components.plc_bridge.plc.vendors.s7_smart.errors import STOP_MESSAGE
from simulators.s7_smart import CODES, HttpFault, S7SmartSimulator
from simulators.s7_smart.errors import (
    INTERNAL_ERROR,
    INVALID_PARAMS,
    INVALID_REQUEST,
    PAYLOAD_TOO_LARGE,
    TOO_MANY_NODES,
)
from tests.loopback import connected

from .conftest import ConfigFactory

pytestmark = pytest.mark.no_pacing

POINTS = [Point(f"VW{2 * index}", "signed") for index in range(40)]
DEEP = "[" * 100_000 + "]" * 100_000


@pytest.mark.parametrize("status", [200, 500])
@pytest.mark.parametrize("codes", CODES)
@pytest.mark.parametrize(
    "refusal", [TOO_MANY_NODES, PAYLOAD_TOO_LARGE, INVALID_PARAMS, INVALID_REQUEST, INTERNAL_ERROR]
)
async def test_node_limit_every_refusal(
    s7_smart_sim: S7SmartSimulator,
    s7_smart_client: S7SmartClient,
    refusal: int,
    codes: str,
    status: int,
) -> None:
    """A firmware taking 10 nodes, refusing more with any code and words (one of them the code
    our old table read as a lost session): the poll finds the limit instead of failing."""
    s7_smart_sim.max_nodes, s7_smart_sim.node_limit_error = 10, refusal
    s7_smart_sim.codes, s7_smart_sim.error_status = codes, status
    s7_smart_sim.set("VW78", 5)
    result = await s7_smart_client.read(POINTS)
    assert result.values[POINTS[-1]].value == 5
    assert all(outcome.ok for outcome in result.values.values())
    assert s7_smart_client.metrics.session_renewals == 0
    before = s7_smart_sim.calls["read"]
    assert all(outcome.ok for outcome in (await s7_smart_client.read(POINTS)).values.values())
    assert s7_smart_sim.calls["read"] - before == 4


async def test_node_limit_then_lost_session(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    """With the limit learned, a lost session is renewed as ever, and counted once."""
    s7_smart_sim.max_nodes = 10
    await s7_smart_client.read(POINTS)
    s7_smart_sim.invalidate_tokens()
    assert all(outcome.ok for outcome in (await s7_smart_client.read(POINTS)).values.values())
    assert s7_smart_client.metrics.session_renewals == 1


async def test_refused_even_one_node(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    """A read refused whole at every size, its session working: the PLC's words, no guess."""
    s7_smart_sim.max_nodes = 0
    with pytest.raises(PlcProtocolError, match=r"refused the request \(Too many nodes., code"):
        await s7_smart_client.read(POINTS[:4])
    assert s7_smart_client.metrics.session_renewals == 0
    assert isinstance((await s7_smart_client.read([])).status.mode, str)  # status still read


@pytest.mark.parametrize("status", [500, 502, 503, 504, 404])
async def test_http_error_resent(
    s7_smart_sim: S7SmartSimulator,
    s7_smart_config: ConfigFactory,
    monkeypatch: pytest.MonkeyPatch,
    status: int,
) -> None:
    """HTTP 5xx or 404 answers (no JSON-RPC) cost resends, not the poll, while the resends fit
    one poll interval (30, 60, 120 ms in 440 ms; READINGS.md row 19)."""
    monkeypatch.setattr(rpc, "BUSY_BACKOFF", 0.03)
    s7_smart_sim.set("VW0", 3)
    async with connected(S7SmartClient(s7_smart_config(poll_interval=0.44))) as client:
        s7_smart_sim.http_faults = [HttpFault(status, "<html>busy</html>")] * 3
        before = s7_smart_sim.requests
        assert (await client.read(POINTS[:2])).values[POINTS[0]].value == 3
        assert s7_smart_sim.requests - before == 4
        s7_smart_sim.http_faults = [HttpFault(status)] * 4
        with pytest.raises(PlcConnectionError, match=f"HTTP {status} 4 times in a row"):
            await client.read(POINTS[:2])
        assert s7_smart_sim.requests - before == 8


@pytest.mark.parametrize("status", [503, 404, 429])
async def test_write_never_sent_twice(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient, status: int
) -> None:
    s7_smart_sim.http_faults = [HttpFault(status, headers={"Retry-After": "0"})]
    with pytest.raises(PlcConnectionError, match=f"HTTP {status}"):
        await s7_smart_client.write({POINTS[0]: 1})
    assert s7_smart_sim.calls["write"] == 0
    assert s7_smart_sim.get("VW0") == 0
    assert (await s7_smart_client.write({POINTS[0]: 1}))[POINTS[0]].ok


async def test_too_many_requests_waited_out(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    """A 429 asking for a second: the read is sent again after it."""
    s7_smart_sim.http_faults = [HttpFault(429, headers={"Retry-After": "1"})]
    before = s7_smart_sim.requests
    assert (await s7_smart_client.read(POINTS[:1])).values[POINTS[0]].ok
    assert s7_smart_sim.requests - before == 2


async def test_too_many_requests_long_back_off(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    """A 429 asking for an hour: that poll fails, and the next sends nothing until the
    (bounded) back-off is over."""
    s7_smart_sim.http_faults = [HttpFault(429, headers={"Retry-After": "3600"})]
    with pytest.raises(PlcConnectionError, match="HTTP 429"):
        await s7_smart_client.read(POINTS[:1])
    before = s7_smart_sim.requests
    with pytest.raises(PlcConnectionError, match="asked to wait"):
        await s7_smart_client.read(POINTS[:1])
    assert s7_smart_sim.requests == before


async def test_http_error_at_connect(
    s7_smart_sim: S7SmartSimulator, s7_smart_config: ConfigFactory
) -> None:
    s7_smart_sim.http_faults = [HttpFault(503)]
    client = S7SmartClient(s7_smart_config())
    try:
        assert (await client.connect()).firmware == "Web API 1.0.0"
        assert s7_smart_sim.requests == 4  # browse twice, login, get_permission
    finally:
        await client.close()


async def test_http_error_other_status(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    """A 400 or 403 without a JSON-RPC answer is no reason to resend."""
    s7_smart_sim.http_faults = [HttpFault(403, "Forbidden")]
    before = s7_smart_sim.requests
    with pytest.raises(PlcProtocolError, match="HTTP 403"):
        await s7_smart_client.read(POINTS[:1])
    assert s7_smart_sim.requests - before == 1


async def test_deeply_nested_reply(
    s7_smart_sim: S7SmartSimulator, s7_smart_config: ConfigFactory
) -> None:
    """JSON nested deeper than the parser goes is a protocol error (setup retried), never
    a RecursionError."""
    s7_smart_sim.http_faults = [HttpFault(200, DEEP)]
    client = S7SmartClient(s7_smart_config())
    try:
        with pytest.raises(PlcProtocolError, match="not JSON"):
            await client.connect()
        await client.connect()
        s7_smart_sim.http_faults = [HttpFault(200, DEEP)]
        with pytest.raises(PlcProtocolError, match="not JSON"):
            await client.read(POINTS[:1])
    finally:
        await client.close()


async def test_nested_node_value(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    def nest(reply: dict[str, object]) -> dict[str, object]:
        value: object = 1
        for _ in range(400):
            value = [value]
        reply["result"]["data"][0]["value"] = value  # type: ignore[index]
        return reply

    s7_smart_sim.rewrite = nest
    outcome = (await s7_smart_client.read(POINTS[:1])).values[POINTS[0]]
    assert isinstance(outcome.error, PlcProtocolError)
    assert len(str(outcome.error)) < 120


@pytest.mark.parametrize("codes", CODES)
async def test_node_refusals_in_the_plcs_words(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient, codes: str
) -> None:
    """A read-only address and a write in STOP refused per node: no guessed meaning of the code
    leads the PLC's message; STOP is told by the reply's status block."""
    s7_smart_sim.codes, s7_smart_sim.stop_refusal = codes, "node"
    point = Point("SMB29", "unsigned")
    error = (await s7_smart_client.write({point: 1}))[point].error
    assert isinstance(error, PlcWriteRefusedError)
    assert str(error).startswith("SMB29: the PLC refused it (")
    missing = Point("VW20478", "signed")
    s7_smart_sim.v_size = 8192
    assert isinstance((await s7_smart_client.write({missing: 1}))[missing].error, PlcAddressError)
    s7_smart_sim.mode = "STOP"
    error = (await s7_smart_client.write({POINTS[0]: 1}))[POINTS[0]].error
    assert isinstance(error, PlcWriteRefusedError)
    assert str(error).startswith(f"VW0: {STOP_MESSAGE} (")
    assert s7_smart_client.metrics.session_renewals == 0


async def test_shuffled_codes_wording(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    """The outside test's firmware: 3006 for STOP and 3005 for read-only, in its own words."""
    s7_smart_sim.codes, s7_smart_sim.stop_refusal = "shuffled", "node"
    point = Point("SMB29", "unsigned")
    error = (await s7_smart_client.write({point: 1}))[point].error
    assert str(error) == "SMB29: the PLC refused it (Address is read only, code 3005)"
    s7_smart_sim.mode = "STOP"
    error = (await s7_smart_client.write({POINTS[0]: 1}))[POINTS[0]].error
    assert str(error) == f"VW0: {STOP_MESSAGE} (CPU is not in RUN mode, code 3006)"


@pytest.mark.parametrize(("version", "shown"), [("1.0.0", "1.0.0"), ("2.7.0.", "2.7.0")])
async def test_version_forms(
    s7_smart_sim: S7SmartSimulator, s7_smart_config: ConfigFactory, version: str, shown: str
) -> None:
    """The manual's browse reply ends the version with a dot (10.3.1); either form is read."""
    s7_smart_sim.version = version
    client = S7SmartClient(s7_smart_config())
    try:
        assert (await client.connect()).firmware == f"Web API {shown}"
    finally:
        await client.close()
