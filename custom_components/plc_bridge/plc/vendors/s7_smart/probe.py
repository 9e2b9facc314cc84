"""Whether an S7-200 SMART's Web API answers at a host: one call it refuses without a login."""

from __future__ import annotations

from typing import Any

import aiohttp

from ...probe import answered, http_answer, json_object, probe_url
from .rpc import PATH


async def answers(
    host: str, port: int, session: aiohttp.ClientSession, timeout: float
) -> dict[str, Any] | None:
    """Answered when a JSON-RPC 2.0 answer comes back for get_permission sent without a token.

    The CPU answers it with an error object (no session); any JSON-RPC answer to the call, in
    whatever HTTP status, is the Web API answering.
    """
    call = {"jsonrpc": "2.0", "method": "get_permission", "id": 1}
    url = probe_url(host, port, PATH, secure=True)
    answer = await http_answer(session, "POST", url, timeout, json=call)
    reply = json_object(answer[2]) if answer is not None else None
    return answered(
        reply is not None
        and reply.get("jsonrpc") == "2.0"
        and reply.get("id") == 1
        and ("error" in reply or "result" in reply)
    )
