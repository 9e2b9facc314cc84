"""Whether a Tecomat's TecoApi answers at a host: GetInfo, sent without credentials."""

from __future__ import annotations

from typing import Any

import aiohttp

from ...probe import answered, http_answer, json_object, probe_url
from .paths import SERVICE


async def answers(
    host: str, port: int, session: aiohttp.ClientSession, timeout: float
) -> dict[str, Any] | None:
    """Answered when GetInfo answers its JSON object, or asks for Digest or Basic credentials.

    TecoApi answers on plain HTTP by default (port 80), as the connection page does.
    """
    url = probe_url(host, port, SERVICE + "GetInfo", secure=False)
    answer = await http_answer(session, "GET", url, timeout)
    if answer is None:
        return None
    status, headers, body = answer
    if status == 401:
        challenge = headers.get("WWW-Authenticate", "").lstrip().lower()
        return answered(challenge.startswith(("digest", "basic")))
    return answered(status == 200 and json_object(body) is not None)
