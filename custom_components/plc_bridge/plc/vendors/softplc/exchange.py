"""One WEB.TLM exchange: POST or PUT `/dt` with `<data>` items, refused items found by halving.

The manual defines no error reply. A 2xx reply is matched item by item; an item that carries
an error attribute or child fails alone. Any other status fails the request: with one item,
that item fails with the PLC's own words; with more, each half is sent again until the items
it refuses are alone (a PLC that fails a request for one bad item, or only the item: both seen
as structure, not as codes). 401 and 403 are authentication, whatever the body says. A status
that HTTP defines as being about the server, not the request (BUSY: 408, 429, 502, 503, 504)
is no verdict on any item: the exchange fails whole, nothing is halved or remembered.
"""

from __future__ import annotations

from collections.abc import Sequence

from ...errors import (
    PlcAddressError,
    PlcAuthenticationError,
    PlcConnectionError,
    PlcError,
    PlcProtocolError,
)
from ...http import HttpTransport
from .document import Item, error_text, parse_reply, request_body
from .planner import ReadItem, place
from .tls import refused_certificate

type Answers = dict[ReadItem, Item | PlcError]
HEADERS = {"Content-Type": "text/xml; charset=utf-8", "Accept": "text/xml"}
BUSY = frozenset({408, 429, 502, 503, 504})


class Refused(PlcAddressError):
    """The PLC refused a request holding only this item, or marked the item failed."""


class Busy(PlcConnectionError):
    """The PLC answered a whole request with a BUSY status: about itself, not the items."""


async def send(
    transport: HttpTransport, method: str, path: str, body: bytes | None, *, certificate: bool
) -> tuple[int, bytes]:
    """Send one request; a TLS alert about our client certificate is an authentication error."""
    try:
        status, _headers, raw = await transport.request(
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
    if status in BUSY:
        said = error_text(raw) or "no reason given"
        raise Busy(f"the PLC cannot answer now (HTTP {status}: {said})")
    return status, raw


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
) -> None:
    """Send the items in one request; record each one's reply item or error in answers."""
    if not items:
        return
    body = request_body((item.ad, item.count, item.values) for item in items)
    status, raw = await send(transport, method, "/dt", body, certificate=certificate)
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
    await exchange(transport, method, items[:half], answers, certificate=certificate)
    await exchange(transport, method, items[half:], answers, certificate=certificate)
