"""One JSON-RPC 2.0 call to an S7-200 SMART (POST /Web_api): the HTTP answer, resend, back-off."""

from __future__ import annotations

import asyncio
from collections.abc import Mapping
from datetime import datetime
import itertools
import json
import logging
import re
import time
from typing import Any

from ...backoff import retry_after as http_retry_after
from ...errors import PlcConnectionError, PlcProtocolError
from ...http import HttpTransport
from .codec import dumps
from .errors import RpcError

_LOGGER = logging.getLogger(__name__)

PATH = "/Web_api"
READING = frozenset({"browse", "login", "get_permission", "read"})
"""Methods that change nothing in the CPU, sent again once after a broken connection or an HTTP
5xx/404 without a JSON-RPC answer (a login sent twice leaves the second token, the one kept)."""
BACKOFF = 2.0
"""Seconds waited after a 429 that names no Retry-After (twice the manual's pacing, 4.2)."""
MAX_BACKOFF = 60.0
"""The longest Retry-After honoured: a PLC asking for more is asked again after a minute."""
MAX_WAIT = 5.0
"""The longest back-off a call waits out; during a longer one, calls fail without sending."""
BUSY_BACKOFF = 1.0
"""Seconds before a read answered busy is sent again, doubled at each busy answer in a row:
from the manual's pacing (4.2), as long as the resend leaves within one poll interval."""
_CHARSET = re.compile(r";\s*charset\s*=\s*\"?([A-Za-z0-9._:-]+)", re.IGNORECASE)


def cookie_header(token: str) -> str:
    """Return the Cookie header for a login token.

    The manual's examples send "Session-Id=<base64>" (curl -b), but do not say whether login
    returns the pair or the bare token. A name=value pair is sent as given; a bare token (whose
    base64 padding may end in "=") gets the name the examples show.
    """
    return token if "=" in token.rstrip("=") else f"Session-Id={token}"


def retry_after(headers: Mapping[str, str], now: datetime | None = None) -> float:
    """Return the seconds a 429 asks to wait (its Retry-After, else BACKOFF), bounded."""
    seconds = http_retry_after(headers, now)
    return BACKOFF if seconds is None else min(seconds, MAX_BACKOFF)


def busy_delays(budget: float, first: float) -> list[float]:
    """Return the waits before each resend of a read answered busy: doubling, within budget."""
    delays: list[float] = []
    delay = first
    while delay > 0 and sum(delays) + delay <= budget:
        delays.append(delay)
        delay *= 2
    return delays


def decode_body(raw: bytes, content_type: str = "") -> tuple[str, bool]:
    """Return the body's text, and True where it was read one character a byte (Latin-1).

    The manual asks for UTF-8 (4.3), or the charset the reply declares; a firmware that puts a
    string's bytes (>= 0x80) into the reply as they are sends neither. Read one character a
    byte, the JSON still parses and every byte of such a string is kept (READINGS.md row 17).
    """
    declared = _CHARSET.search(content_type)
    try:
        return raw.decode(declared[1] if declared else "utf-8-sig"), False
    except (UnicodeDecodeError, LookupError):
        return raw.decode("latin-1"), True


def _json(text: str) -> Any:
    """Return the parsed body, or None when it is no JSON (nor JSON this parser can nest)."""
    try:
        return json.loads(text)
    except (ValueError, RecursionError):
        return None


class WebApi:
    """The client's JSON-RPC endpoint: call ids, the HTTP status of each answer, back-off."""

    def __init__(self, transport: HttpTransport, host: str, poll_interval: float) -> None:
        """Send through the client's one transport (its lock paces every request).

        `poll_interval`: how long a read answered busy may be sent again for.
        """
        self._transport = transport
        self._host = host
        self._poll_interval = poll_interval
        self._ids = itertools.count(1)
        self._not_before = 0.0
        self._bytewise_told = False

    async def call(self, method: str, params: Any, token: str | None) -> dict[str, Any]:
        """Send one call (never a batch) and return its result object; raise RpcError.

        An HTTP 5xx, 404 or 429 without a JSON-RPC answer (a busy web server, a proxy) is
        sent again for a method that only reads, with back-off (`busy_delays`, at least a
        429's Retry-After) as long as the resend leaves within one poll interval of the first
        send; a write never twice. A 429 also holds back any later call.
        """
        call_id = next(self._ids)
        body = dumps({"jsonrpc": "2.0", "method": method, "id": call_id, "params": params})
        headers = {"Content-Type": "application/json"}
        if token is not None:
            headers["Cookie"] = cookie_header(token)
        reading = method in READING
        delays = busy_delays(self._poll_interval, BUSY_BACKOFF)
        deadline = time.monotonic() + self._poll_interval
        for attempt in itertools.count(1):
            await self._wait(method)
            status, answer_headers, raw = await self._transport.request(
                "POST", PATH, data=body.encode(), headers=headers, idempotent=reading
            )
            text, bytewise = decode_body(raw, answer_headers.get("Content-Type", ""))
            reply = _json(text)
            if 200 <= status < 300 or _answers(reply, call_id):
                if bytewise and reply is not None:
                    self._tell_bytewise()
                return _result(method, call_id, status, reply)
            wait = 0.0
            if status == 429:
                wait = retry_after(answer_headers)
                self._not_before = time.monotonic() + wait
            elif status < 500 and status != 404:
                raise PlcProtocolError(f"the PLC answered {method} with HTTP {status}")
            if reading and attempt <= len(delays):
                wait = max(wait, delays[attempt - 1])
            if not reading or attempt > len(delays) or time.monotonic() + wait > deadline:
                times = f" {attempt} times in a row" if attempt > 1 else ""
                raise PlcConnectionError(f"the PLC answered {method} with HTTP {status}{times}")
            _LOGGER.debug(
                "%s answered HTTP %s: %s sent again in %.1f s", PATH, status, method, wait
            )
            await asyncio.sleep(wait)
        raise AssertionError  # pragma: no cover - the loop returns or raises

    def _tell_bytewise(self) -> None:
        """Log once that the PLC sends text that is not UTF-8, and how its strings are shown."""
        if not self._bytewise_told:
            self._bytewise_told = True
            _LOGGER.warning(
                "%s sends strings whose bytes are not UTF-8 (the Web API manual asks for UTF-8): "
                "they are shown one character a byte (Latin-1), each byte kept; text in another "
                "code page (GBK, Windows-1250) shows as Latin-1 letters",
                self._host,
            )

    async def _wait(self, method: str) -> None:
        """Wait out a short back-off a 429 asked for; refuse to send during a long one."""
        left = self._not_before - time.monotonic()
        if left > MAX_WAIT:
            raise PlcConnectionError(
                f"the PLC asked to wait {left:.0f} s more before {method} (HTTP 429)"
            )
        if left > 0:
            await asyncio.sleep(left)


def _answers(reply: Any, call_id: int) -> bool:
    """Say whether a body is a JSON-RPC answer to this call (a firmware may send one with 500)."""
    return (
        isinstance(reply, dict)
        and reply.get("jsonrpc") == "2.0"
        and (reply.get("id") in (call_id, str(call_id)) or reply.get("id") is None)
        and isinstance(reply.get("error"), dict)
    )


def _result(method: str, call_id: int, status: int, reply: Any) -> dict[str, Any]:
    """Return the result object of an answer; raise RpcError for its error object."""
    if reply is None:
        raise PlcProtocolError(f"the PLC answered {method} with HTTP {status}, not JSON")
    if not isinstance(reply, dict) or reply.get("jsonrpc") != "2.0":
        raise PlcProtocolError(f"the PLC's answer to {method} is not JSON-RPC 2.0")
    error = reply.get("error")
    # The manual's templates quote the echoed id ("${id_in_requests}"): accept it as text too.
    # An error about the request itself (parse error, too large) may carry a null id.
    if reply.get("id") not in (call_id, str(call_id)) and not (
        reply.get("id") is None and isinstance(error, dict)
    ):
        raise PlcProtocolError(
            f"the PLC answered id {reply.get('id')!r} to request id {call_id} ({method})"
        )
    if isinstance(error, dict):
        code, message = error.get("code"), error.get("message")
        raise RpcError(
            code if isinstance(code, int) else 0, message if isinstance(message, str) else ""
        )
    result = reply.get("result")
    if not isinstance(result, dict):
        raise PlcProtocolError(f"the PLC's answer to {method} has no result")
    return result
