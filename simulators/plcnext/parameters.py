"""Request parameters of the PLCnext simulator: JSON or form bodies, queries, path lists, faults."""

from __future__ import annotations

import json
from typing import Any
from urllib.parse import parse_qs

from aiohttp import web


class Fault(Exception):
    """An error answer: status, reason, and the WWW-Authenticate of a token refusal."""

    def __init__(self, status: int, reason: str, challenge: str = "") -> None:
        super().__init__(status, reason)
        self.status, self.reason, self.challenge = status, reason, challenge


def body_fields(body: bytes) -> dict[str, Any]:
    """Return a body's parameters: JSON (sniffed, whatever the content type) or a form."""
    text = body.decode("utf-8", "replace").strip()
    if text.startswith("{"):
        try:
            data = json.loads(text)
        except ValueError:
            raise Fault(400, "invalidJson") from None
        return data if isinstance(data, dict) else {}
    return {key: values[-1] for key, values in parse_qs(text).items()}


def query_fields(request: web.Request) -> dict[str, Any]:
    """Return the query's parameters (a trailing `&`, as pyPLCn sends, is harmless)."""
    return {key: request.query.getone(key) for key in request.query}


def paths_of(raw: Any) -> list[str]:
    """Return the `paths` parameter: a JSON list, or a comma-separated text."""
    if isinstance(raw, list):
        return [str(path) for path in raw]
    if isinstance(raw, str):
        return [path for path in raw.split(",") if path.strip()]
    return []


def number(raw: Any, default: float) -> float:
    """Return a number parameter sent as text or JSON."""
    try:
        return float(raw)
    except (TypeError, ValueError):
        return default
