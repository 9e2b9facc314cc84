"""Whether a PLCnext Control's REST data interface answers at a host: its service description."""

from __future__ import annotations

from typing import Any

import aiohttp

from ...probe import answered, http_answer, json_object, probe_url
from .api import LATEST


async def answers(
    host: str, port: int, session: aiohttp.ClientSession, timeout: float
) -> dict[str, Any] | None:
    """Answered when the service description (asked before any login) names an API version."""
    answer = await http_answer(session, "GET", probe_url(host, port, LATEST, secure=True), timeout)
    if answer is None or not 200 <= answer[0] < 300:
        return None
    description = json_object(answer[2])
    return answered(
        description is not None
        and any(isinstance(description.get(key), str) for key in ("version", "apiVersion"))
    )
