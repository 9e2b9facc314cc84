"""The S7-200 SMART client's session, refusals, malformed replies and TLS modes."""

from __future__ import annotations

import asyncio
import time
from typing import Any

import aiohttp
import pytest

from custom_components.plc_bridge.plc import (
    PlcAuthenticationError,
    PlcConnectionError,
    PlcProtocolError,
    PlcTlsError,
    PlcWriteRefusedError,
    Point,
    TlsMode,
)
from custom_components.plc_bridge.plc.vendors.s7_smart import (
    S7SmartClient,
    session as session_module,
)
from custom_components.plc_bridge.plc.vendors.s7_smart.errors import STOP_MESSAGE
from simulators.s7_smart import S7SmartSimulator

from .conftest import ConfigFactory
from .s7_smart_fixtures import FIRMWARES, configure, firmware_id

pytestmark = pytest.mark.no_pacing

POINT = Point("VW0", "signed")


@pytest.fixture(autouse=True, params=FIRMWARES, ids=firmware_id)
def firmware(request: pytest.FixtureRequest, s7_smart_sim: S7SmartSimulator) -> dict[str, Any]:
    """Run every session, STOP and permission test under each reading the manual leaves open:
    codes of our table, foreign ones, or ours meaning other things; STOP refused for the whole
    write or per node; error replies with HTTP 200 or 500; a login cookie with its name or bare.
    The paths rest on structure."""
    configure(s7_smart_sim, request.param)
    return dict(request.param)


async def stop_refusal(client: S7SmartClient, point: Point) -> str:
    """Write in STOP and return the refusal's text, whole request or node alike."""
    try:
        error = (await client.write({point: 1}))[point].error
    except PlcWriteRefusedError as err:
        error = err
    assert isinstance(error, PlcWriteRefusedError)
    return str(error)


async def test_token_renewed_once(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    s7_smart_sim.set("VW0", 9)
    s7_smart_sim.invalidate_tokens()
    assert (await s7_smart_client.read([POINT])).values[POINT].value == 9
    assert s7_smart_client.metrics.session_renewals == 1
    assert s7_smart_sim.calls["login"] == 2
    await s7_smart_client.read([POINT])
    assert s7_smart_client.metrics.session_renewals == 1


async def test_token_lost_twice_fails(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    """A refusal that a fresh login does not cure is no reason for reauth (the login worked);
    an empty read refused too tells a dropped session, whatever the code says."""
    s7_smart_sim.idle_timeout = 0.0  # every token is stale by its next request
    with pytest.raises(PlcConnectionError, match="refused calls again right after a new login"):
        await s7_smart_client.read([POINT, Point("VW2", "signed")])
    assert s7_smart_client.metrics.session_renewals == 0  # the retry failed: nothing renewed
    assert s7_smart_client.metrics.errors == 1
    assert s7_smart_sim.calls["login"] == 2
    assert s7_smart_sim.calls["read"] == 3  # no node-count probing with a session that fails


async def test_idle_expiry(s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient) -> None:
    await s7_smart_client.read([POINT])
    assert s7_smart_client.metrics.session_renewals == 0
    # Shortened only now: on a busy machine the first read may take longer than the timeout.
    s7_smart_sim.idle_timeout = 0.5  # long beside the new login's retry, even on a busy machine
    await asyncio.sleep(0.6)
    assert (await s7_smart_client.read([POINT])).values[POINT].ok
    assert s7_smart_client.metrics.session_renewals == 1


async def test_renewal_then_other_refusal(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    s7_smart_sim.invalidate_tokens()
    s7_smart_sim.mode = "STOP"
    assert STOP_MESSAGE in await stop_refusal(s7_smart_client, POINT)
    assert s7_smart_client.metrics.session_renewals == 1


@pytest.mark.parametrize(("user", "password"), [("admin", "wrong"), ("nobody", "Smart-200")])
async def test_login_refused(
    s7_smart_sim: S7SmartSimulator, s7_smart_config: ConfigFactory, user: str, password: str
) -> None:
    client = S7SmartClient(s7_smart_config(username=user, password=password))
    with pytest.raises(PlcAuthenticationError, match="refused the user name or password"):
        await client.connect()
    await client.close()
    assert s7_smart_sim.calls["login"] == 1
    assert s7_smart_sim.calls["logout"] == 0


async def test_login_without_token(
    s7_smart_sim: S7SmartSimulator, s7_smart_config: ConfigFactory
) -> None:
    def drop_cookie(reply: dict[str, Any]) -> dict[str, Any]:
        reply["result"].pop("cookie", None)
        return reply

    s7_smart_sim.rewrite = drop_cookie
    client = S7SmartClient(s7_smart_config())
    with pytest.raises(PlcProtocolError, match="sent no token"):
        await client.connect()
    await client.close()


async def test_bare_token_gets_cookie_name(
    s7_smart_sim: S7SmartSimulator, s7_smart_config: ConfigFactory
) -> None:
    s7_smart_sim.cookie_name_in_token = False
    client = S7SmartClient(s7_smart_config())
    await client.connect()
    assert (await client.read([POINT])).values[POINT].ok
    await client.close()


async def test_stop_refuses_writes(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    s7_smart_sim.mode = "STOP"
    refusal = await stop_refusal(s7_smart_client, POINT)
    assert STOP_MESSAGE in refusal
    assert "value" not in refusal  # no guessed meaning of a code; the PLC's words follow
    assert s7_smart_client.metrics.session_renewals == 0  # the status told: no new login
    assert s7_smart_sim.calls["login"] == 1
    assert (await s7_smart_client.read([POINT])).status.mode == "STOP"


async def test_no_write_permission(
    s7_smart_config: ConfigFactory, firmware: dict[str, Any]
) -> None:
    """A read-only user's write is refused as such, whatever code the firmware uses."""
    sim = S7SmartSimulator(write_permission=False)
    configure(sim, firmware)
    await sim.start()
    try:
        client = S7SmartClient(s7_smart_config(port=sim.port, fingerprint=sim.fingerprint))
        assert (await client.connect()).can_write is False
        with pytest.raises(PlcWriteRefusedError, match="no write permission"):
            await client.write({POINT: 1})
        assert sim.calls["login"] == 1  # the empty read passed: no new login to try
        await client.close()
    finally:
        await sim.stop()


async def test_malformed_reply(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    s7_smart_sim.malformed = True
    with pytest.raises(PlcProtocolError, match="not JSON"):
        await s7_smart_client.read([POINT])
    with pytest.raises(PlcProtocolError):
        await s7_smart_client.write({POINT: 1})


@pytest.mark.parametrize(
    ("rewrite", "message"),
    [
        (lambda r: r | {"id": r["id"] + 100}, "answered id"),
        (lambda r: r | {"id": None}, "answered id None"),
        (lambda r: r | {"jsonrpc": "1.0"}, "not JSON-RPC 2.0"),
        (lambda r: [r], "not JSON-RPC 2.0"),
        (lambda r: {"jsonrpc": "2.0", "id": r["id"]}, "has no result"),
        (lambda r: r | {"result": r["result"] | {"data": r["result"]["data"][:1]}}, "1 nodes"),
        (lambda r: r | {"result": r["result"] | {"data": None}}, "answered no nodes"),
        (lambda r: r | {"result": r["result"] | {"data": [{"var": "VW2"}] * 2}}, "match"),
        (
            lambda r: {"jsonrpc": "2.0", "id": None, "error": {"code": 2003, "message": "Big."}},
            "the PLC refused the request \\(Big., code 2003\\)",
        ),
        (
            lambda r: {"jsonrpc": "2.0", "id": r["id"], "error": {"code": "x"}},
            "the PLC refused the request \\(no message, code 0\\)",
        ),
        (
            lambda r: {"jsonrpc": "2.0", "id": r["id"], "error": {"code": 5, "message": [["x"]]}},
            "the PLC refused the request \\(no message, code 5\\)",
        ),
    ],
)
async def test_protocol_errors(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient, rewrite: Any, message: str
) -> None:
    """Garbled or refused read replies (not the login's or the empty status read's); a refusal
    survives the one fresh login it earns and a read of fewer nodes."""
    s7_smart_sim.rewrite = lambda reply: rewrite(reply) if reply["result"].get("data") else reply
    with pytest.raises(PlcProtocolError, match=message):
        await s7_smart_client.read([POINT, Point("VW2", "signed")])


async def test_id_echoed_as_text(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    s7_smart_sim.rewrite = lambda reply: reply | {"id": str(reply["id"])}
    assert (await s7_smart_client.read([POINT])).values[POINT].ok


async def test_tls_modes(s7_smart_sim: S7SmartSimulator, s7_smart_config: ConfigFactory) -> None:
    wrong = S7SmartClient(s7_smart_config(fingerprint="00" * 32))
    with pytest.raises(PlcTlsError, match="pinned"):
        await wrong.connect()
    await wrong.close()
    assert s7_smart_sim.requests == 0
    verify = S7SmartClient(s7_smart_config(tls=TlsMode.VERIFY))
    with pytest.raises(PlcTlsError):
        await verify.connect()
    await verify.close()
    assert s7_smart_sim.requests == 0
    off = S7SmartClient(s7_smart_config(tls=TlsMode.OFF, fingerprint=""))
    await off.connect()
    assert (await off.read([POINT])).values[POINT].ok
    await off.close()


async def test_close_logs_out(
    s7_smart_sim: S7SmartSimulator, s7_smart_config: ConfigFactory
) -> None:
    async with aiohttp.ClientSession() as session:
        client = S7SmartClient(s7_smart_config(), session)
        await client.connect()
        await client.close()
        assert s7_smart_sim.calls["logout"] == 1
        assert not session.closed  # an injected session belongs to its owner
        assert (await client.read([POINT])).values[POINT].ok  # logs in again, no renewal
        assert client.metrics.session_renewals == 0
        assert s7_smart_sim.calls["login"] == 2
        await client.close()


async def test_close_when_plc_is_gone(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    own = s7_smart_client.session
    await s7_smart_sim.stop()
    await s7_smart_client.close()
    assert own.closed


async def test_close_does_not_wait_for_a_silent_plc(
    monkeypatch: pytest.MonkeyPatch, s7_smart_config: ConfigFactory
) -> None:
    async def silent(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        await reader.read()

    server = await asyncio.start_server(silent, "127.0.0.1", 0)
    port = server.sockets[0].getsockname()[1]
    monkeypatch.setattr(session_module, "LOGOUT_TIMEOUT", 0.05)
    client = S7SmartClient(s7_smart_config(port=port, tls=TlsMode.OFF, fingerprint=""))
    client._token = "Session-Id=abc"  # logged in before the PLC went silent
    client._http()
    started = time.monotonic()
    await client.close()
    assert time.monotonic() - started < 1
    server.close()
    await server.wait_closed()


async def test_concurrent_calls_share_one_login(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    """Calls at once after the session was lost log in once: a second login would end the first."""
    s7_smart_sim.invalidate_tokens()
    logins = s7_smart_sim.calls["login"]
    results = await asyncio.gather(*(s7_smart_client.read([POINT]) for _ in range(3)))
    assert all(result.values[POINT].ok for result in results)
    assert s7_smart_sim.calls["login"] == logins + 1


async def test_calls_without_a_session_share_one_login(s7_smart_config: ConfigFactory) -> None:
    """A client that never logged in: calls at once make one login between them."""
    client = S7SmartClient(s7_smart_config())
    try:
        await asyncio.gather(*(client.read([POINT]) for _ in range(3)))
        assert client._logins == 1
    finally:
        await client.close()


async def test_fewer_nodes_learned(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    """A firmware taking 10 nodes a read, whatever code it refuses with: after the one fresh
    login, fewer nodes are tried until the most that pass is found; the limit is kept, for
    writes too; no renewal is counted (the retry after the login failed) and no error raised."""
    s7_smart_sim.max_nodes = 10
    points = [Point(f"VW{2 * index}", "signed") for index in range(40)]
    result = await s7_smart_client.read(points)
    assert all(outcome.ok for outcome in result.values.values())
    assert s7_smart_client.metrics.session_renewals == 0
    assert s7_smart_sim.calls["login"] == 2
    before = s7_smart_sim.calls["read"]
    await s7_smart_client.read(points)
    assert s7_smart_sim.calls["read"] - before == 4  # 40 nodes, 10 a request
    written = await s7_smart_client.write(dict.fromkeys(points[:20], 3))
    assert all(outcome.ok for outcome in written.values())
    assert s7_smart_sim.calls["write"] == 2
    assert s7_smart_sim.calls["login"] == 2


async def test_write_past_an_unknown_limit_is_sent_again_smaller(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    """A firmware taking 8 nodes, not met by reads yet: a write of 20 refused whole is sent
    again in requests of the limit reads of the same nodes find; every value arrives once."""
    s7_smart_sim.max_nodes = 8
    points = [Point(f"VW{2 * index}", "signed") for index in range(20)]
    written = await s7_smart_client.write({point: index for index, point in enumerate(points)})
    assert all(outcome.ok for outcome in written.values())
    assert [s7_smart_sim.get(point.address) for point in points] == list(range(20))
    assert s7_smart_sim.calls["write"] == 1 + 3  # refused whole, then 8 + 8 + 4
    before = s7_smart_sim.calls["read"]
    await s7_smart_client.read(points)
    assert s7_smart_sim.calls["read"] - before == 3  # the limit is kept for polls


async def test_write_refused_whole_for_another_reason_fails(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    """A write refused whole while a read of the same nodes passes: nothing learned, no resend."""
    points = [Point(f"VW{2 * index}", "signed") for index in range(4)]
    await s7_smart_client.read(points)
    s7_smart_sim.max_write_nodes = 2
    with pytest.raises(PlcWriteRefusedError, match="refused the write"):
        await s7_smart_client.write(dict.fromkeys(points, 1))
    assert s7_smart_sim.calls["write"] == 1
    assert s7_smart_client._max_nodes == 32


async def test_write_beside_a_read_after_the_session_was_lost(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient
) -> None:
    """A poll and a write at once, their token ended by another login: the poll's new login
    lands before the write's empty read, which passes on the new token. The write is sent again
    on it, not taken for refused; one login between them."""
    s7_smart_sim.invalidate_tokens()
    logins = s7_smart_sim.calls["login"]
    written = Point("VW2", "signed")
    read, result = await asyncio.gather(
        s7_smart_client.read([POINT]), s7_smart_client.write({written: 5})
    )
    assert read.values[POINT].ok
    assert result[written].ok
    assert s7_smart_sim.get("VW2") == 5
    assert s7_smart_sim.calls["login"] == logins + 1
