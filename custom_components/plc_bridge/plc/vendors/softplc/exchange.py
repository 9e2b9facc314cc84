"""One WEB.TLM exchange: POST or PUT `/dt` with `<data>` items, refused items found by halving.

The manual defines no error reply. A 2xx reply is matched item by item; an item that carries
an error attribute or child fails alone. Any other status fails the request: with one item,
that item fails with the PLC's own words; with more, each half is sent again until the items
it refuses are alone (a PLC that fails a request for one bad item, or only the item: both seen
as structure, not as codes). 401 and 403 are authentication, whatever the body says. A status
that HTTP defines as being about the server, not the request (BUSY: 408, 429, 502, 503, 504)
is no verdict on any item: nothing is halved or remembered. A read (GET, or POST /dt) so
answered is sent once more after the wait its Retry-After asks (or a short back-off), when that
wait fits in a poll interval; a PUT never twice. The manual names no status at all (READINGS.md,
row 14): HTTP says 408, 429 and 503 are answered before the request is acted on, so a PUT
answered so wrote nothing; behind a 502 or 504 (a gateway) the PLC may have written.
"""

from __future__ import annotations

import asyncio
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
import logging
import time

from ...backoff import retry_after
from ...errors import (
    PlcAddressError,
    PlcAuthenticationError,
    PlcConnectionError,
    PlcError,
    PlcProtocolError,
    PlcWriteRefusedError,
)
from ...http import HttpTransport
from .document import Item, error_text, parse_reply, request_body
from .planner import ReadItem, place
from .tls import refused_certificate

type Answers = dict[ReadItem, Item | PlcError]
HEADERS = {"Content-Type": "text/xml; charset=utf-8", "Accept": "text/xml"}
BUSY = frozenset({408, 429, 502, 503, 504})
NOT_TAKEN = frozenset({408, 429, 503})
"""BUSY statuses sent before the request is acted on (RFC 9110 15.5.9, 15.6.4; RFC 6585 4)."""
READS = frozenset({"GET", "POST"})
"""Requests that change nothing in the PLC (POST /dt: the manual's reads of many items)."""
BACKOFF = 1.0
"""Seconds waited before a read is sent again after a BUSY answer naming no Retry-After."""

_LOGGER = logging.getLogger(__name__)


class Refused(PlcAddressError):
    """The PLC refused a request holding only this item, or marked the item failed."""


class Busy(PlcConnectionError):
    """The PLC answered a whole request with a BUSY status: about itself, not the items."""


@dataclass(slots=True)
class Patience:
    """How long a busy PLC is waited for (`limit`: the poll interval) and until when."""

    limit: float
    not_before: float = 0.0

    def wait(self, seconds: float) -> None:
        """Remember that the PLC asked to be left alone for this long from now."""
        self.not_before = max(self.not_before, time.monotonic() + seconds)

    async def wait_out(self, method: str) -> None:
        """Sleep out a wait the PLC asked for; a read during a longer one fails unsent."""
        left = self.not_before - time.monotonic()
        if left <= 0:
            return
        if left > self.limit:
            raise Busy(f"the PLC asked to be left alone {left:.0f} s more (Retry-After)")
        _LOGGER.debug("WEB.TLM busy: %s waits %.1f s", method, left)
        await sleep(left)
        self.not_before = 0.0


async def sleep(seconds: float) -> None:
    """Wait (one name, so a test can see the waits asked for)."""
    await asyncio.sleep(seconds)


async def send(
    transport: HttpTransport,
    method: str,
    path: str,
    body: bytes | None,
    *,
    certificate: bool,
    patience: Patience | None = None,
) -> tuple[int, bytes]:
    """Send one request; a read answered BUSY is sent once more (`Patience`), a PUT never."""
    for attempt in (1, 2):
        if patience is not None and method in READS:
            await patience.wait_out(method)
        status, headers, raw = await _send_once(
            transport, method, path, body, certificate=certificate
        )
        if status not in BUSY:
            return status, raw
        said = f"HTTP {status}: {error_text(raw) or 'no reason given'}"
        if method == "PUT" and status in NOT_TAKEN:
            raise PlcWriteRefusedError(f"the PLC did not take the write, nothing written ({said})")
        if method == "PUT":
            raise Busy(f"the PLC's gateway answered the write with {said}: it may be written")
        asked = retry_after(headers)
        if patience is None or attempt == 2 or (asked or 0.0) > patience.limit:
            if patience is not None and asked is not None:
                patience.wait(asked)
            raise Busy(f"the PLC cannot answer now ({said})")
        patience.wait(min(BACKOFF, patience.limit) if asked is None else asked)
        _LOGGER.debug("%s %s answered %s: sent again", method, path, said)
    raise AssertionError  # pragma: no cover - the loop returns or raises


async def _send_once(
    transport: HttpTransport, method: str, path: str, body: bytes | None, *, certificate: bool
) -> tuple[int, Mapping[str, str], bytes]:
    """Send one request; a TLS alert about our client certificate is an authentication error."""
    try:
        status, headers, raw = await transport.request(
            method,
            path,
            data=body,
            headers=HEADERS if body is not None else None,
            idempotent=method == "POST",  # POST /dt only reads (manual: reads of many items)
        )
    except PlcError as err:
        if certificate and refused_certificate(err):
            raise PlcAuthenticationError(
                "the PLC refused the client certificate during the TLS handshake"
            ) from None
        raise
    if status in (401, 403):
        raise PlcAuthenticationError(_refusal(method, status, raw, certificate=certificate))
    return status, headers, raw


def _refusal(method: str, status: int, raw: bytes, *, certificate: bool) -> str:
    """Return the words of an authentication refusal (PUT: the client certificate)."""
    said = error_text(raw) or "no reason given"
    if method != "PUT":
        return f"the PLC refused the request ({status}: {said})"
    if certificate:
        return f"the PLC refused the client certificate for writes ({status}: {said})"
    return (
        f"the PLC takes writes only with a client certificate ({status}: {said}); "
        "add one in the PLC's connection settings (HTTPS)"
    )


async def exchange(
    transport: HttpTransport,
    method: str,
    items: Sequence[ReadItem],
    answers: Answers,
    *,
    certificate: bool,
    patience: Patience | None = None,
) -> None:
    """Send the items in one request; record each one's reply item or error in answers."""
    if not items:
        return
    body = request_body((item.ad, item.count, item.values) for item in items)
    status, raw = await send(
        transport, method, "/dt", body, certificate=certificate, patience=patience
    )
    if 200 <= status < 300:
        placed, ambiguous = place(items, parse_reply(raw))
        for item in items:
            answer = placed.get(item)
            if item in ambiguous:
                answers[item] = PlcProtocolError(
                    f"the PLC's answer cannot be told apart for {item.ad}: its items name the "
                    "same place as another's"
                )
            elif answer is None:
                answers[item] = PlcProtocolError(f"{item.ad} is missing from the PLC's answer")
            elif answer.error:
                answers[item] = Refused(f"the PLC refused {item.ad}: {answer.error[:200]}")
            else:
                answers[item] = answer
        return
    if len(items) == 1:
        said = error_text(raw) or "no reason given"
        answers[items[0]] = Refused(f"the PLC refused {items[0].ad} ({status}: {said})")
        return
    half = len(items) // 2
    for part in (items[:half], items[half:]):
        await exchange(transport, method, part, answers, certificate=certificate, patience=patience)
