"""What a vendor's probe shares: one short, unauthenticated request that tells whether it answers.

A probe sends nothing secret and logs in nowhere; it only says "this interface answers here",
so that a discovered host is offered with the right PLC family. Each vendor module has its own
`answers(host, port, session, timeout)` that asks what only its interface answers.
"""

from __future__ import annotations

import asyncio
from collections.abc import Awaitable, Callable, Mapping
import json
from typing import Any

import aiohttp
from yarl import URL

PROBE_BODY = 16 * 1024
"""The most of an answer's body a probe reads: enough for an error object or a description."""

type Probe = Callable[[str, int, aiohttp.ClientSession, float], Awaitable[dict[str, Any] | None]]
"""A vendor's probe: host, port, HTTP session and timeout in; None where its interface does not
answer, else the connection options it answered with (an S7 CPU's slot; mostly none)."""


def answered(found: bool) -> dict[str, Any] | None:
    """Return the result of a probe that only tells whether the interface answered."""
    return {} if found else None


def probe_url(host: str, port: int, path: str, *, secure: bool) -> URL:
    """Return the address of a path on the host (IPv6 addresses bracketed)."""
    return URL.build(scheme="https" if secure else "http", host=host, port=port, path=path)


async def http_answer(
    session: aiohttp.ClientSession,
    method: str,
    url: URL,
    timeout: float,
    **arguments: Any,
) -> tuple[int, Mapping[str, str], bytes] | None:
    """Send one request; return status, headers and the body's start, None where none answers.

    The certificate is not checked: the probe trusts nothing it reads beyond which interface
    answers, and the connection page that follows pins or checks it before any password is sent.
    """
    try:
        async with (
            asyncio.timeout(timeout),
            session.request(method, url, ssl=False, allow_redirects=False, **arguments) as answer,
        ):
            return answer.status, answer.headers, await answer.content.read(PROBE_BODY)
    except (aiohttp.ClientError, OSError, ValueError):  # TimeoutError is an OSError
        return None


def json_object(body: bytes) -> dict[str, Any] | None:
    """Return a body parsed as a JSON object, or None when it is no JSON object."""
    try:
        parsed = json.loads(body)
    except (ValueError, RecursionError):
        return None
    return parsed if isinstance(parsed, dict) else None
