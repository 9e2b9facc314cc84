"""The shared HTTP choke point: TLS modes, pinning, error mapping, pacing."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncGenerator
import socket
import ssl
import time

import aiohttp
from aiohttp import web
import pytest

from custom_components.plc_bridge.plc import (
    ClientMetrics,
    ConnectionConfig,
    PlcConnectionError,
    PlcProtocolError,
    PlcTimeoutError,
    PlcTlsError,
    TlsMode,
)
from custom_components.plc_bridge.plc.http import (
    HttpTransport,
    base_url,
    client_session,
    fetch_fingerprint,
    format_fingerprint,
)
from simulators.base import HttpSimulator
from tests.loopback import running


class EchoSimulator(HttpSimulator):
    """Answers /echo with the body it got, /slow after a pause."""

    def build_app(self, app: web.Application) -> None:
        async def echo(request: web.Request) -> web.Response:
            return web.Response(body=await request.read())

        async def slow(request: web.Request) -> web.Response:
            await asyncio.sleep(1)
            return web.Response(text="late")

        async def big(request: web.Request) -> web.StreamResponse:
            size = int(request.query["size"])
            if request.query.get("chunked"):  # no Content-Length: only the read can stop it
                response = web.StreamResponse()
                response.enable_chunked_encoding()
                await response.prepare(request)
                for _ in range(size // 1000):
                    await response.write(b"x" * 1000)
                await response.write_eof()
                return response
            return web.Response(body=b"x" * size)

        app.router.add_post("/echo", echo)
        app.router.add_get("/slow", slow)
        app.router.add_get("/big", big)


class TlsEchoSimulator(EchoSimulator):
    """The same over HTTPS with a device-CA certificate."""

    tls = True


@pytest.fixture
async def session() -> AsyncGenerator[aiohttp.ClientSession]:
    async with aiohttp.ClientSession() as client_session:
        yield client_session


@pytest.fixture
async def tls_sim() -> AsyncGenerator[TlsEchoSimulator]:
    async with running(TlsEchoSimulator()) as sim:
        yield sim


def _transport(
    session: aiohttp.ClientSession, port: int, tls: TlsMode, fingerprint: str = "", **kw: float
) -> tuple[HttpTransport, ClientMetrics]:
    config = ConnectionConfig(
        host="127.0.0.1", port=port, tls=tls, fingerprint=fingerprint, timeout=kw.pop("timeout", 5)
    )
    metrics = ClientMetrics()
    return HttpTransport(config, session, metrics, **kw), metrics


async def test_pinned_certificate_accepted(
    session: aiohttp.ClientSession, tls_sim: TlsEchoSimulator
) -> None:
    assert tls_sim.fingerprint
    transport, metrics = _transport(session, tls_sim.port, TlsMode.PIN, tls_sim.fingerprint)
    status, _headers, body = await transport.request("POST", "/echo", data=b"hi")
    assert (status, body, metrics.requests, tls_sim.requests) == (200, b"hi", 1, 1)


async def test_changed_certificate_refused(
    session: aiohttp.ClientSession, tls_sim: TlsEchoSimulator
) -> None:
    assert tls_sim.fingerprint
    pinned = tls_sim.fingerprint
    tls_sim.new_certificate()
    await tls_sim.restart()
    transport, _ = _transport(session, tls_sim.port, TlsMode.PIN, pinned)
    with pytest.raises(PlcTlsError, match="pinned"):
        await transport.request("POST", "/echo", data=b"secret")
    assert tls_sim.requests == 0


async def test_verify_refuses_device_ca(
    session: aiohttp.ClientSession, tls_sim: TlsEchoSimulator
) -> None:
    transport, _ = _transport(session, tls_sim.port, TlsMode.VERIFY)
    with pytest.raises(PlcTlsError):
        await transport.request("POST", "/echo")


async def test_tls_off_and_fingerprint_fetch(
    session: aiohttp.ClientSession, tls_sim: TlsEchoSimulator
) -> None:
    transport, _ = _transport(session, tls_sim.port, TlsMode.OFF)
    assert (await transport.request("POST", "/echo", data=b"x"))[2] == b"x"
    assert await fetch_fingerprint("127.0.0.1", tls_sim.port) == tls_sim.fingerprint


def test_bad_pinned_fingerprint() -> None:
    config = ConnectionConfig(host="h", port=1, tls=TlsMode.PIN, fingerprint="zz")
    with pytest.raises(PlcTlsError):
        HttpTransport(config, None, ClientMetrics())  # type: ignore[arg-type]


async def test_plain_http_timeout_and_pacing(session: aiohttp.ClientSession) -> None:
    sim = EchoSimulator()
    await sim.start()
    try:
        transport, _ = _transport(session, sim.port, TlsMode.NONE, request_interval=0.05)
        started = time.monotonic()
        await transport.request("POST", "/echo")
        await transport.request("POST", "/echo")
        assert time.monotonic() - started >= 0.05
        slow, _ = _transport(session, sim.port, TlsMode.NONE, timeout=0.05)
        with pytest.raises(PlcTimeoutError):
            await slow.request("GET", "/slow")
        with pytest.raises(PlcTlsError):
            await fetch_fingerprint("127.0.0.1", sim.port)
    finally:
        await sim.stop()


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
        return port


async def test_unreachable(session: aiohttp.ClientSession) -> None:
    port = _free_port()
    transport, _ = _transport(session, port, TlsMode.NONE)
    with pytest.raises(PlcConnectionError):
        await transport.request("GET", "/")
    with pytest.raises(PlcConnectionError):
        await fetch_fingerprint("127.0.0.1", port)


def test_urls_and_formatting() -> None:
    assert base_url(ConnectionConfig(host="::1", port=443, tls=TlsMode.PIN)) == "https://[::1]:443"
    assert base_url(ConnectionConfig(host="plc", port=80)) == "http://plc:80"
    assert format_fingerprint("ab01ff") == "AB:01:FF"


@pytest.mark.parametrize(("interval", "connections"), [(60.0, 1), (5.0, 2)])
async def test_own_session_keeps_connection_for_poll_interval(
    tls_sim: TlsEchoSimulator,
    monkeypatch: pytest.MonkeyPatch,
    interval: float,
    connections: int,
) -> None:
    """Idle 60 s between two requests: a 60 s poller reuses its TLS connection, a 5 s one not.

    aiohttp's own default (15 s, Home Assistant's shared connector) would open a new one.
    """
    now = [time.monotonic()]
    monkeypatch.setattr("aiohttp.connector.monotonic", lambda: now[0])
    config = ConnectionConfig(
        host="127.0.0.1",
        port=tls_sim.port,
        tls=TlsMode.PIN,
        fingerprint=tls_sim.fingerprint or "",
        poll_interval=interval,
    )
    async with client_session(config) as own:
        transport = HttpTransport(config, own, ClientMetrics())
        await transport.request("POST", "/echo", data="1")
        now[0] += 60.0
        await transport.request("POST", "/echo", data="2")
    assert len(tls_sim.peers) == connections


@pytest.mark.parametrize("chunked", ["", "1"])
async def test_reply_body_capped(session: aiohttp.ClientSession, chunked: str) -> None:
    """A reply past the cap is a protocol error, with or without a Content-Length."""
    sim = EchoSimulator()
    await sim.start()
    try:
        transport, _metrics = _transport(session, sim.port, TlsMode.NONE, max_body=10_000)
        status, _headers, body = await transport.request(
            "GET", f"/big?size=10000&chunked={chunked}"
        )
        assert (status, len(body)) == (200, 10_000)
        with pytest.raises(PlcProtocolError, match=r"10000 bytes|too large"):
            await transport.request("GET", f"/big?size=20000&chunked={chunked}")
    finally:
        await sim.stop()


async def test_own_ssl_context_replaces_tls_mode(
    session: aiohttp.ClientSession, tls_sim: TlsEchoSimulator
) -> None:
    """A vendor's own SSL context decides the check: one trusting nothing refuses the PLC."""
    context = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)  # no CA loaded: nothing is trusted
    config = ConnectionConfig(host="127.0.0.1", port=tls_sim.port, tls=TlsMode.OFF, timeout=5)
    transport = HttpTransport(config, session, ClientMetrics(), ssl_context=context)
    with pytest.raises(PlcTlsError):
        await transport.request("POST", "/echo", data="1")


class ClosingServer:
    """Answers the first request of each connection, then closes it at the next request.

    What a PLC does that closes an idle kept-alive connection just as a poll reuses it.
    """

    def __init__(self) -> None:
        self.connections = 0
        self.server: asyncio.Server | None = None

    async def handle(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        self.connections += 1
        for answered in (False, True):
            try:
                head = await reader.readuntil(b"\r\n\r\n")
            except asyncio.IncompleteReadError:  # the client closed it first
                break
            length = next(
                (
                    int(line.split(b":")[1])
                    for line in head.split(b"\r\n")
                    if line.lower().startswith(b"content-length")
                ),
                0,
            )
            await reader.readexactly(length)
            if answered:
                break
            writer.write(
                b"HTTP/1.1 200 OK\r\nContent-Length: 2\r\nConnection: keep-alive\r\n\r\nok"
            )
            await writer.drain()
        writer.close()

    async def __aenter__(self) -> int:
        self.server = await asyncio.start_server(self.handle, "127.0.0.1", 0)
        return int(self.server.sockets[0].getsockname()[1])

    async def __aexit__(self, *_: object) -> None:
        assert self.server is not None
        self.server.close()
        self.server.close_clients()  # the client's pool still holds the second one
        await self.server.wait_closed()


@pytest.mark.parametrize("idempotent", [True, False])
async def test_reading_post_sent_again_on_a_closed_kept_alive_connection(
    session: aiohttp.ClientSession, idempotent: bool
) -> None:
    """A POST that only reads survives a kept-alive connection the PLC closed; a write fails."""
    server = ClosingServer()
    async with server as port:
        transport, metrics = _transport(session, port, TlsMode.NONE)
        assert (await transport.request("POST", "/read", data="1"))[2] == b"ok"
        if idempotent:
            status, _headers, body = await transport.request(
                "POST", "/read", data="2", idempotent=True
            )
            assert (status, body, server.connections, metrics.requests) == (200, b"ok", 2, 3)
        else:
            with pytest.raises(PlcConnectionError):
                await transport.request("POST", "/write", data="2")
            assert server.connections == 1
