"""TecoApi authentication (Digest with nonce renewal, Basic, refusals) and the TLS modes."""

from __future__ import annotations

import base64
from typing import TYPE_CHECKING

import pytest

from custom_components.plc_bridge.plc import (
    PlcAuthenticationError,
    PlcConnectionError,
    PlcTlsError,
    Point,
    TlsMode,
)
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient
from custom_components.plc_bridge.plc.vendors.tecomat.api import basic_authorization
from simulators.tecomat import TecomatSimulator

if TYPE_CHECKING:
    from .tecomat_fixtures import ConfigFactory


POINTS = [Point("plcName", "STRING"), Point("Main.myObject3.value", "REAL")]


async def test_digest_challenge(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    assert tecomat_sim.requests == 2  # GetInfo unauthenticated: 401.023 and its challenge, again
    before = tecomat_sim.requests
    await tecomat_client.read(POINTS)
    await tecomat_client.write({POINTS[1]: 21.5})
    # read, write, write read back: the nonce is reused, no challenge per request
    assert tecomat_sim.requests - before == 3
    assert tecomat_sim.auth.accepted == {"digest auth-int": 4}  # auth-int hashes the PUT body
    assert tecomat_client.metrics.session_renewals == 0


async def test_digest_stale_nonce_mid_poll(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    items = await tecomat_client.browse()
    points = [Point(i.address, i.data_type) for i in items if i.address.startswith("plcData")]
    assert TecomatClient.requests_for(points) == 2
    answers = 0

    def stale_after_first(body: bytes) -> bytes:
        nonlocal answers
        answers += 1
        if answers == 1:  # the PLC renews its nonce between the poll's two requests
            tecomat_sim.stale_nonce()
        return body

    tecomat_sim.rewrite = stale_after_first
    before, sent = tecomat_sim.requests, tecomat_client.metrics.requests
    result = await tecomat_client.read(points)
    assert all(outcome.ok for outcome in result.values.values())
    assert tecomat_sim.requests - before == 3  # 401.020 "New balls", then the same request
    assert tecomat_client.metrics.requests - sent == 2  # as the client sees them
    assert tecomat_client.metrics.session_renewals == 1
    await tecomat_client.read(points)
    assert tecomat_client.metrics.session_renewals == 1


async def test_two_stale_nonces_are_no_wrong_password(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    tecomat_sim.stale_nonce(times=2)  # 401.020 "New balls", and again for the renewed nonce
    with pytest.raises(PlcConnectionError, match="nonce twice in a row") as caught:
        await tecomat_client.read(POINTS)
    assert not isinstance(caught.value, PlcAuthenticationError)  # no reauth for good credentials
    assert tecomat_client.metrics.session_renewals == 2
    assert (await tecomat_client.read(POINTS)).values[POINTS[0]].value == "myFoxtrot"


async def test_basic(tecomat_config: ConfigFactory) -> None:
    sim = TecomatSimulator(auth="basic", bench=0)
    await sim.start()
    client = TecomatClient(tecomat_config(port=sim.port, options={"auth": "basic"}))
    try:
        await client.connect()
        assert sim.requests == 1  # Basic credentials go with the first request
        assert (await client.read(POINTS)).values[POINTS[0]].value == "myFoxtrot"
        assert sim.auth.accepted == {"basic": 2}
    finally:
        await client.close()
        await sim.stop()


@pytest.mark.parametrize("auth", ["digest", "basic"])
async def test_wrong_password(tecomat_config: ConfigFactory, auth: str) -> None:
    sim = TecomatSimulator(auth=auth, bench=0)
    await sim.start()
    client = TecomatClient(tecomat_config(port=sim.port, password="wrong", options={"auth": auth}))
    try:
        with pytest.raises(PlcAuthenticationError, match="refused the user name or password"):
            await client.connect()
    finally:
        await client.close()
        await sim.stop()


@pytest.mark.parametrize(
    ("server", "client_auth", "message"),
    [
        ("basic", "digest", "asks for basic authentication, not digest; choose basic"),
        ("digest", "basic", "does not accept basic authentication"),
        ("digest", "ntlm", "unknown authentication 'ntlm'"),
    ],
)
async def test_method_mismatch(
    tecomat_config: ConfigFactory, server: str, client_auth: str, message: str
) -> None:
    sim = TecomatSimulator(auth=server, bench=0)
    await sim.start()
    client = TecomatClient(tecomat_config(port=sim.port, options={"auth": client_auth}))
    try:
        with pytest.raises(PlcAuthenticationError, match=message):
            await client.connect()
    finally:
        await client.close()
        await sim.stop()


async def test_user_name_with_colon(tecomat_config: ConfigFactory) -> None:
    client = TecomatClient(tecomat_config(username="a:b"))
    with pytest.raises(PlcAuthenticationError, match="user name cannot be used"):
        await client.connect()
    await client.close()


async def test_unknown_user(tecomat_sim: TecomatSimulator, tecomat_config: ConfigFactory) -> None:
    client = TecomatClient(tecomat_config(username="guest"))
    with pytest.raises(PlcAuthenticationError, match="user name or password"):
        await client.connect()
    await client.close()


@pytest.mark.parametrize("mode", [TlsMode.PIN, TlsMode.OFF, TlsMode.VERIFY])
async def test_https(tecomat_config: ConfigFactory, mode: TlsMode) -> None:
    sim = TecomatSimulator(tls=True, bench=0)
    await sim.start()
    assert sim.fingerprint is not None
    config = tecomat_config(port=sim.port, tls=mode, fingerprint=sim.fingerprint)
    client = TecomatClient(config)
    try:
        if mode is TlsMode.VERIFY:
            with pytest.raises(PlcTlsError):
                await client.connect()
        else:
            assert (await client.connect()).serial == "PP 0004"
            assert (await client.read(POINTS)).values[POINTS[0]].value == "myFoxtrot"
    finally:
        await client.close()
        await sim.stop()


def test_class_attributes() -> None:
    assert TecomatClient.default_port == 80
    assert TecomatClient.default_tls is TlsMode.NONE
    assert TecomatClient.tls_modes == (TlsMode.NONE, TlsMode.PIN, TlsMode.VERIFY, TlsMode.OFF)
    assert TecomatClient.can_browse
    assert TecomatClient.needs_credentials


def test_basic_authorization_header() -> None:
    """Basic credentials as RFC 7617 encodes them; a ':' in the user name cannot be sent."""
    assert basic_authorization("Aladdin", "open sesame") == "Basic QWxhZGRpbjpvcGVuIHNlc2FtZQ=="
    assert basic_authorization("jürg", "x") == "Basic " + base64.b64encode(b"j\xfcrg:x").decode()
    assert basic_authorization("u", "€") == "Basic " + base64.b64encode("u:€".encode()).decode()
    with pytest.raises(PlcAuthenticationError, match="cannot contain"):
        basic_authorization("a:b", "x")
