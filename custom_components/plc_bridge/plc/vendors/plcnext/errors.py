"""PLCnext error answers: read the error object, say what went wrong by the answer's structure.

The sources document the statuses (401 token, 404 unknown group or names, 408, 410 session
gone) and the shape `{"error": {"details": [{"reason": "<camelCase>", ...}]}}`, and name a few
reasons (`wrongPassword`, `invalidNames`, `invalidSessionID`, `accessDenied`). Decisions here
follow the status and the request; a reason only adds the PLC's own words to a message.
"""

from __future__ import annotations

import json
from typing import Any

from ...errors import (
    PlcAuthenticationError,
    PlcConnectionError,
    PlcError,
    PlcProtocolError,
    PlcTimeoutError,
    PlcWriteRefusedError,
)


class ApiError(Exception):
    """An answer that is not 2xx; the client handles some statuses itself and maps the others."""

    def __init__(self, status: int, reasons: tuple[str, ...], challenge: str = "") -> None:
        super().__init__(status, reasons)
        self.status = status
        self.reasons = reasons
        self.challenge = challenge  # WWW-Authenticate of a 401

    @property
    def words(self) -> str:
        """The PLC's reasons and the status, for a message."""
        said = ", ".join(self.reasons) or "no reason given"
        return f"HTTP {self.status}: {said}"


def reasons_of(error: Any) -> tuple[str, ...]:
    """Return the reasons an error object gives (`details[].reason`, or a bare text)."""
    if isinstance(error, str):
        return (error.strip()[:80],) if error.strip() else ()
    if not isinstance(error, dict):
        return ()
    found: list[str] = []
    details = error.get("details")
    for detail in details if isinstance(details, list) else [error]:
        if isinstance(detail, dict):
            for key in ("reason", "message", "code"):
                value = detail.get(key)
                if isinstance(value, str | int) and not isinstance(value, bool) and str(value):
                    found.append(str(value)[:80])
                    break
    return tuple(found)


def parse_error(status: int, raw: bytes, challenge: str = "") -> ApiError:
    """Return the error of an answer that is not 2xx, with whatever reasons its body gives."""
    error: Any = None
    try:
        body = json.loads(raw)
    except (ValueError, RecursionError):
        body = raw.decode("utf-8", "replace")
    if isinstance(body, dict):
        error = body.get("error", body)
    elif isinstance(body, str):
        error = body
    reasons = reasons_of(error)
    if not reasons and "error=" in challenge:  # Bearer realm="pxcapi", error="invalid_token"
        reasons = (challenge.partition("error=")[2].strip().strip('"'),)
    return ApiError(status, reasons, challenge)


def request_error(error: ApiError, *, write: bool = False) -> PlcError:
    """Return the exception for an error answer to a whole request, by its status."""
    if error.status == 401:
        return PlcAuthenticationError(f"the PLC refused the access token ({error.words})")
    if error.status == 403:
        if write:
            return PlcWriteRefusedError(
                f"the PLC refused the write: the variable is read-only or the user may not "
                f"change variables ({error.words})"
            )
        return PlcAuthenticationError(
            f"the PLC user may not read HMI variables: give it an EHmi role ({error.words})"
        )
    if error.status == 408:
        return PlcTimeoutError(f"the PLC timed out serving the request ({error.words})")
    if error.status >= 500:
        return PlcConnectionError(f"the PLC could not serve the request ({error.words})")
    return PlcProtocolError(f"the PLC refused the request ({error.words})")
