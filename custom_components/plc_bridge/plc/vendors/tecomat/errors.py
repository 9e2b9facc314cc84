"""TecoApi error answers (3.7): read the error body, map a whole-request failure to a PlcError."""

from __future__ import annotations

from collections.abc import Sequence
import contextlib
import json
import re
from typing import Any

from ...errors import (
    PlcAddressError,
    PlcAuthenticationError,
    PlcConnectionError,
    PlcError,
    PlcProtocolError,
)
from .paths import Segment, VariablePath, parse_path

NOT_FOUND = "400.005"  # Variable 'NNN' is not found
NOT_WRITTEN = "400.015"  # Value VVV was not written to variable 'NNN' (type of variable is TTT)
TOO_MANY_REQUESTED = "413.002"
TOO_MANY_ITEMS = "413.004"
NEW_BALLS = "401.020"  # Digest stale=true
BAD_CREDENTIALS = "401.021"
UNSUPPORTED_AUTH = "403.022"
AUTH_REQUESTED = "401.023"
NO_VARIABLES = "400.006"
PUBLIC_FILE = ("500.010", "500.011", "500.012")

_NOT_FOUND = re.compile(r"Variable '(.*)' is not found", re.DOTALL)
_NOT_WRITTEN = re.compile(
    r"Value (.*) was not written to variable '(.*)' \(type of variable is (.*)\)", re.DOTALL
)


class TecoError(Exception):
    """An error answer; the client handles some codes itself and maps the others."""

    def __init__(self, status: int, code: str, message: str, challenge: str = "") -> None:
        super().__init__(code, message)
        self.status = status
        self.code = code
        self.message = message
        self.challenge = challenge  # WWW-Authenticate of a 401


def parse_error(status: int, raw: bytes, challenge: str = "") -> TecoError:
    """Return the error of an answer that is not 2xx; its code is "HTTP status.Teco code"."""
    error: Any = None
    with contextlib.suppress(ValueError, AttributeError, RecursionError):
        error = json.loads(raw).get("error")
    if not isinstance(error, dict) or not isinstance(error.get("code"), str):
        text = raw.decode("utf-8", "replace").strip()[:120]
        return TecoError(status, f"{status}.000", text or f"HTTP {status}", challenge)
    return TecoError(status, error["code"].strip(), str(error.get("message", "")), challenge)


def missing_variable(error: TecoError) -> str | None:
    """Return the variable a 400.005 answer names."""
    match = _NOT_FOUND.search(error.message) if error.code == NOT_FOUND else None
    return match[1] if match else None


def refused(error: TecoError) -> bool:
    """True for a refusal of some variable (400.005, 400.015), whatever its text says.

    3.7 words them in English with the name; a localised or newer firmware words them
    otherwise (simulators/tecomat/READINGS.md, "error texts"): the code alone is enough to
    narrow a request down.
    """
    return error.code in (NOT_FOUND, NOT_WRITTEN)


def refused_value(error: TecoError) -> tuple[str, str, str] | None:
    """Return (value, variable, PLC type) of a 400.015 answer."""
    match = _NOT_WRITTEN.search(error.message) if error.code == NOT_WRITTEN else None
    return (match[1], match[2], match[3]) if match else None


def blame(paths: Sequence[VariablePath], name: str) -> tuple[list[int], int] | None:
    """Return the positions of the paths an error's name points at, and its length; or None.

    The length is how many segments of those paths name the unknown variable. The PLC names
    the whole path, or only the item where it stopped walking it: `sport` for
    myObject.favorites.sport, `favorites` when that member is gone. A name that fits one
    variable (with all that lies inside it) is sure; fitting none or several, the caller splits
    the request to find out. A lone path is always the one (the whole of it, unless the name
    fits one of its items).
    """
    try:
        wanted = _folded(parse_path(name).segments)
    except PlcAddressError:
        wanted = ()
    variables: dict[tuple[Segment, ...], list[int]] = {}
    for index, path in enumerate(paths):
        parts = _folded(path.segments)
        for start in range(len(parts) - len(wanted) + 1 if wanted else 0):
            if parts[start : start + len(wanted)] == wanted:
                variables.setdefault(parts[: start + len(wanted)], []).append(index)
                break
    if len(variables) == 1:
        prefix, positions = next(iter(variables.items()))
        return positions, len(prefix)
    return ([0], len(paths[0].segments)) if len(paths) == 1 else None


def _folded(segments: tuple[Segment, ...]) -> tuple[Segment, ...]:
    """Return path segments as the PLC compares them: names case-insensitively."""
    return tuple(part.lower() if isinstance(part, str) else part for part in segments)


def request_error(error: TecoError, auth: str) -> PlcError:
    """Return the exception for an error answer to a whole request."""
    code, message = error.code, error.message
    if code == BAD_CREDENTIALS:
        return PlcAuthenticationError("the PLC refused the user name or password")
    if code == NEW_BALLS:  # a nonce renewed twice in a row says nothing about the password
        return PlcConnectionError(
            "the PLC renewed its digest nonce twice in a row (401.020); the next request "
            "uses the new one"
        )
    if code == UNSUPPORTED_AUTH:
        return PlcAuthenticationError(f"the PLC does not accept {auth} authentication")
    if error.status == 401:
        offered = error.challenge.partition(" ")[0].lower()
        if offered and offered != auth:
            return PlcAuthenticationError(
                f"the PLC asks for {offered} authentication, not {auth}; choose {offered}"
            )
        return PlcAuthenticationError(f"the PLC did not accept the credentials: {message}")
    if code in PUBLIC_FILE:
        return PlcProtocolError(
            f"the PLC cannot serve its variables ({message}): build the program in Mosaic "
            "with {PUBLIC_API} variables and let it send its files to the PLC"
        )
    if code == NO_VARIABLES:
        return PlcProtocolError("the PLC program publishes no variables ({PUBLIC_API})")
    return PlcProtocolError(f"the PLC refused the request: {message} ({code})")
