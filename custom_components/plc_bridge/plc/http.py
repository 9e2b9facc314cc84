"""The one HTTP choke point the HTTP vendors share: TLS mode, timeout, pacing, error mapping."""

from __future__ import annotations

import asyncio
from collections import deque
from collections.abc import Iterable, Iterator, Mapping
from contextlib import contextmanager, suppress
from contextvars import ContextVar
import hashlib
import logging
import re
import ssl
import time
from typing import Any

import aiohttp
from yarl import URL

from .errors import PlcConnectionError, PlcProtocolError, PlcTimeoutError, PlcTlsError
from .types import ClientMetrics, ConnectionConfig, TlsMode

URGENT: ContextVar[bool] = ContextVar("plc_bridge_urgent", default=False)
"""True inside `urgent()`: the requests sent there end an output (a pulse's off)."""


@contextmanager
def urgent() -> Iterator[None]:
    """Send the requests made inside as urgent: they go first and wait out no pacing.

    For the writes that release an output (a pulse's off, an interlock's release): a paced
    PLC must not keep an output on for another request interval.
    """
    token = URGENT.set(True)
    try:
        yield
    finally:
        URGENT.reset(token)


def ssl_option(config: ConnectionConfig) -> aiohttp.Fingerprint | bool | None:
    """Return the aiohttp `ssl=` argument for the configured TLS mode."""
    if config.tls is TlsMode.PIN:
        try:
            return aiohttp.Fingerprint(bytes.fromhex(config.fingerprint))
        except ValueError as err:
            raise PlcTlsError("the pinned certificate fingerprint is not valid") from err
    if config.tls is TlsMode.OFF:
        return False
    if config.tls is TlsMode.VERIFY:
        return True
    return None


KEEPALIVE_MARGIN = 15.0
"""Seconds a connection is kept idle beyond the poll interval (a late poll still finds it)."""
KEEPALIVE_MAX = 1800.0
"""The longest idle connection kept: the S7-200 SMART's session idles out after 30 minutes."""


def keepalive_timeout(config: ConnectionConfig) -> float:
    """Return how long an idle connection to this PLC is kept: the poll interval, and a margin.

    aiohttp's default (15 s, also Home Assistant's shared connector) closes it between polls
    whenever the interval is longer, so every poll would pay a new TCP and TLS handshake, which
    the S7-200 SMART manual (4.2, "Use long connections") calls slow and costly for the CPU.
    """
    return min(config.poll_interval + KEEPALIVE_MARGIN, KEEPALIVE_MAX)


def client_session(
    config: ConnectionConfig, ssl_context: ssl.SSLContext | None = None
) -> aiohttp.ClientSession:
    """Return an HTTP session of one PLC's own, whose idle connection outlives a poll interval.

    `ssl_context`: what TlsMode.VERIFY checks against (the system CAs when None); a pinned or
    unchecked certificate is decided per request (`ssl_option`). The resolver runs in the
    executor: a PLC is most often an IP address, which needs none.
    """
    connector = aiohttp.TCPConnector(
        keepalive_timeout=keepalive_timeout(config),
        ssl=ssl_context if ssl_context is not None else True,
        resolver=aiohttp.ThreadedResolver(),
    )
    return aiohttp.ClientSession(connector=connector)


def base_url(config: ConnectionConfig) -> str:
    """Return scheme://host:port for the configured TLS mode (IPv6 hosts bracketed)."""
    scheme = "http" if config.tls is TlsMode.NONE else "https"
    host = f"[{config.host}]" if ":" in config.host else config.host
    return f"{scheme}://{host}:{config.port}"


async def fetch_fingerprint(host: str, port: int, timeout: float = 10.0) -> str:
    """Connect once without verification and return the SHA-256 hex of the server certificate."""
    return hashlib.sha256(await fetch_certificate(host, port, timeout)).hexdigest()


async def fetch_certificate(host: str, port: int, timeout: float = 10.0) -> bytes:
    """Connect once without verification and return the server certificate (DER)."""
    # A bare context: create_default_context() would load the system CAs, a blocking read,
    # and this handshake trusts nothing anyway; it only looks at the certificate.
    context = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)
    context.check_hostname = False
    context.verify_mode = ssl.CERT_NONE
    try:
        async with asyncio.timeout(timeout):
            _reader, writer = await asyncio.open_connection(host, port, ssl=context)
    except TimeoutError as err:
        raise PlcTimeoutError(f"no answer from {host}:{port}") from err
    except ssl.SSLError as err:
        raise PlcTlsError(f"TLS handshake with {host}:{port} failed: {err.reason}") from err
    except OSError as err:
        raise PlcConnectionError(f"cannot connect to {host}:{port}: {err.strerror}") from err
    try:
        ssl_object = writer.get_extra_info("ssl_object")
        der = ssl_object.getpeercert(binary_form=True) if ssl_object else None
    finally:
        writer.close()
    if not der:
        raise PlcTlsError(f"{host}:{port} presented no certificate")
    return bytes(der)


def format_fingerprint(fingerprint: str) -> str:
    """Return a fingerprint as colon-separated upper-case byte pairs, as browsers show it."""
    return ":".join(fingerprint[i : i + 2] for i in range(0, len(fingerprint), 2)).upper()


_LOGGER = logging.getLogger(__name__)
SECRET_FIELDS = (
    "password",
    "passwd",
    "token",
    "access_token",
    "auth_token",
    "refresh_token",
    "cookie",
    "username",
    "user",
)
"""JSON fields a request or reply may carry credentials or a session in: never logged."""


def secret_fields(names: Iterable[str]) -> re.Pattern[str]:
    """Return the pattern of JSON string fields whose values a debug line masks."""
    alternatives = "|".join(re.escape(name) for name in names)
    # A value runs to its closing quote (an escaped \" does not end it), or to the end of a
    # body cut short.
    return re.compile(rf'("(?:{alternatives})"\s*:\s*)"(?:[^"\\]|\\.)*"?', re.IGNORECASE)


SECRET = secret_fields(SECRET_FIELDS)
SHOWN = 500
"""Characters of a body a debug line shows."""


def shown(body: str | bytes | None, secret: re.Pattern[str] = SECRET) -> str:
    """Return a body as the debug log shows it: credentials and tokens masked, cut short."""
    if body is None:
        return ""
    text = body.decode("utf-8", "replace") if isinstance(body, bytes) else body
    text = secret.sub(r'\1"***"', text)
    return text if len(text) <= SHOWN else f"{text[:SHOWN]}… ({len(text)} characters)"


MAX_BODY = 16 * 1024 * 1024
"""The largest reply body read (a PLC's largest real answer is far below a megabyte)."""


async def _read_capped(response: aiohttp.ClientResponse, limit: int) -> bytes:
    """Return the body, refusing it as soon as it grows past `limit` bytes (never buffered)."""
    if response.content_length is not None and response.content_length > limit:
        raise PlcProtocolError(f"the PLC's reply of {response.content_length} bytes is too large")
    chunks: list[bytes] = []
    size = 0
    async for chunk in response.content.iter_chunked(64 * 1024):
        size += len(chunk)
        if size > limit:
            raise PlcProtocolError(f"the PLC's reply is larger than {limit} bytes: refused")
        chunks.append(chunk)
    return b"".join(chunks)


class Turns:
    """Whose turn the transport is: waiting urgent requests first, each kind in arrival order.

    An `asyncio.Lock` serves strictly in arrival order; a pulse's off must not queue behind
    a paced poll's remaining requests.
    """

    def __init__(self) -> None:
        """Start free, with nobody waiting."""
        self._busy = False
        self._urgent: deque[asyncio.Future[None]] = deque()
        self._others: deque[asyncio.Future[None]] = deque()
        self._pause: asyncio.Future[None] | None = None

    async def take(self, urgent: bool) -> None:
        """Wait for the turn; an urgent request ends a pacing pause of the one holding it."""
        if not self._busy:
            self._busy = True
            return
        if urgent and self._pause is not None and not self._pause.done():
            self._pause.set_result(None)
        await self._wait(self._urgent if urgent else self._others, first=False)

    def give(self) -> None:
        """Hand the turn to the first urgent request waiting, else the first other one."""
        for queue in (self._urgent, self._others):
            while queue:
                waiter = queue.popleft()
                if not waiter.done():
                    waiter.set_result(None)
                    return  # still busy: the turn was handed on
        self._busy = False

    async def pause(self, seconds: float) -> None:
        """Wait out pacing holding the turn, unless an urgent request comes: it goes first.

        The turn comes back after every urgent request waiting, before any other request.
        """
        self._pause = asyncio.get_running_loop().create_future()
        try:
            if not self._urgent:
                await asyncio.wait((self._pause,), timeout=seconds)
        finally:
            self._pause.cancel()
            self._pause = None
        if self._urgent:
            self.give()
            await self._wait(self._others, first=True)

    async def _wait(self, queue: deque[asyncio.Future[None]], *, first: bool) -> None:
        """Queue up and wait until `give` hands the turn over."""
        waiter = asyncio.get_running_loop().create_future()
        if first:
            queue.appendleft(waiter)
        else:
            queue.append(waiter)
        try:
            await waiter
        except asyncio.CancelledError:
            if waiter.cancelled():
                with suppress(ValueError):
                    queue.remove(waiter)
            else:  # handed the turn as the wait was cancelled: pass it on
                self.give()
            raise


class HttpTransport:
    """Sends every request of one client: one lock, one timeout, pacing and error mapping."""

    def __init__(
        self,
        config: ConnectionConfig,
        session: aiohttp.ClientSession,
        metrics: ClientMetrics,
        *,
        request_interval: float = 0.0,
        ssl_context: ssl.SSLContext | None = None,
        max_body: int = MAX_BODY,
        secrets: Iterable[str] = (),
    ) -> None:
        """Bind the transport to a PLC, an aiohttp session and the client's metrics.

        `ssl_context` replaces the TLS mode's check (a vendor that presents a client
        certificate builds one, and checks the PLC's certificate in it); `max_body` caps a
        reply's body while it is read (PlcProtocolError beyond it); `secrets` names more JSON
        fields the debug log masks (a vendor's own token fields).
        """
        self._config = config
        self._session = session
        self._metrics = metrics
        self._ssl: aiohttp.Fingerprint | ssl.SSLContext | bool | None = (
            ssl_context if ssl_context is not None else ssl_option(config)
        )
        self._max_body = max_body
        extra = tuple(secrets)
        self._secret = secret_fields((*SECRET_FIELDS, *extra)) if extra else SECRET
        self._url = base_url(config)
        self._timeout = aiohttp.ClientTimeout(total=config.timeout)
        self._turns = Turns()
        self._interval = request_interval
        self._last = 0.0

    async def request(
        self,
        method: str,
        path: str,
        *,
        data: str | bytes | None = None,
        headers: Mapping[str, str] | None = None,
        encoded: bool = False,
        idempotent: bool = False,
        **kwargs: Any,
    ) -> tuple[int, Mapping[str, str], bytes]:
        """Send one request and return status, headers and body; map every failure.

        `encoded`: the path is sent exactly as given (no percent-encoding of `[`, `]`, ...).
        `idempotent`: a POST that only reads. Sent again once when the connection breaks
        before an answer, as aiohttp does for GET and PUT (RFC 9112 9.3.1): a kept-alive
        connection the PLC closed while idle must not fail a poll.
        """
        url: str | URL = URL(self._url + path, encoded=True) if encoded else self._url + path
        arguments = {"data": data, "headers": headers, **kwargs}
        is_urgent = URGENT.get()
        await self._turns.take(is_urgent)
        try:
            # Capped: a clock that moved back (suspend, a frozen test clock) never stalls a poll.
            while (
                not is_urgent
                and (wait := min(self._interval, self._last + self._interval - time.monotonic()))
                > 0
            ):
                await self._turns.pause(wait)
            try:
                try:
                    return await self._send(method, url, path, arguments)
                except (aiohttp.ClientOSError, aiohttp.ServerDisconnectedError) as err:
                    if not idempotent or isinstance(err, aiohttp.ClientConnectorError):
                        raise
                    _LOGGER.debug("%s: connection lost before an answer, sent again", path)
                    return await self._send(method, url, path, arguments)
            except aiohttp.ServerFingerprintMismatch as err:
                raise PlcTlsError(
                    "the PLC presented a certificate other than the pinned one"
                ) from err
            except aiohttp.ClientConnectorCertificateError as err:
                raise PlcTlsError(
                    f"the PLC certificate is not trusted: {err.certificate_error}"
                ) from err
            except aiohttp.ClientSSLError as err:
                raise PlcTlsError(f"TLS failed: {err}") from err
            except TimeoutError as err:
                raise PlcTimeoutError(f"no answer from {self._config.host} in time") from err
            except aiohttp.ClientResponseError as err:
                raise PlcProtocolError(f"malformed HTTP reply: {err.message}") from err
            except aiohttp.ClientConnectorError as err:
                # Its text names the ssl argument, a pin's `Fingerprint object at 0x…`: say why.
                raise PlcConnectionError(
                    f"cannot reach {self._config.host}:{self._config.port}: {err.os_error}"
                ) from err
            except (aiohttp.ClientError, OSError) as err:
                raise PlcConnectionError(f"cannot reach {self._config.host}: {err}") from err
            finally:
                self._last = time.monotonic()
        finally:
            self._turns.give()

    async def _send(
        self, method: str, url: str | URL, path: str, arguments: dict[str, Any]
    ) -> tuple[int, Mapping[str, str], bytes]:
        """Send one request (counted) and read its answer; aiohttp's errors pass through."""
        self._metrics.requests += 1
        started = time.monotonic()
        async with self._session.request(
            method,
            url,
            ssl=self._ssl if self._ssl is not None else True,
            timeout=self._timeout,
            **arguments,
        ) as response:
            body = await _read_capped(response, self._max_body)
            # Headers are never logged: they carry the Authorization and the Cookie.
            if _LOGGER.isEnabledFor(logging.DEBUG):  # masking a body costs more than a request
                _LOGGER.debug(
                    "%s %s %s %s -> %s in %.0f ms: %s",
                    self._config.host,
                    method,
                    path,
                    shown(arguments["data"], self._secret),
                    response.status,
                    (time.monotonic() - started) * 1000,
                    shown(body, self._secret),
                )
            return response.status, response.headers, body
