"""S7-200 SMART refusals: the PLC's own words behind a neutral lead, kinds told by structure.

The manual's error page is missing: its only code is 3004 "Invalid address." (the read and
write examples, 8.3.1 and 9.3.1). Any other code or message is a firmware's own, so none of
them decides what happened: the method refused, the status block of a reply or of an empty read
(8.1 d), and whether a fresh login cured it do (client.S7SmartClient._call). READINGS.md in
simulators/s7_smart lists the readings the simulator answers with.
"""

from __future__ import annotations

import reprlib
from typing import Any

from ...errors import (
    PlcAddressError,
    PlcAuthenticationError,
    PlcConnectionError,
    PlcError,
    PlcProtocolError,
    PlcWriteRefusedError,
)

INVALID_ADDRESS = 3004
INVALID_ADDRESS_TEXT = "Invalid address."
STOP_MESSAGE = "the PLC is in STOP; S7-200 SMART accepts writes only in RUN"


class RpcError(Exception):
    """A JSON-RPC error answer; the client turns it into a PlcError and never lets it out."""

    def __init__(self, code: int, message: str) -> None:
        """Keep the PLC's code and message."""
        super().__init__(code, message)
        self.code = code
        self.message = message

    @property
    def words(self) -> str:
        """What the PLC said: its message and its code."""
        return said(self.message, self.code)


class RequestRefused(PlcProtocolError):
    """The PLC refused a whole read that a fresh login did not cure, its session working."""


class WriteRefused(PlcWriteRefusedError):
    """The PLC refused a whole write, its session working, in RUN, the user allowed to write."""


def said(message: Any, code: Any) -> str:
    """Return the PLC's message (or that it gave none) and its code, for an error's text."""
    text = message.strip() if isinstance(message, str) else ""
    return f"{text or 'no message'}, code {reprlib.repr(code)}"


def login_error(err: RpcError) -> PlcError:
    """Return the error of a refused login (manual 5.3.2: an error object, whatever its code)."""
    return PlcAuthenticationError(f"the PLC refused the user name or password ({err.words})")


def session_error(err: RpcError) -> PlcError:
    """Return the error of calls refused again, an empty read too, right after a login that worked.

    The password is right (not a case for reauth); most likely another client logs in as the
    same PLC user, each login ending the other's token (manual 5.1 b).
    """
    return PlcConnectionError(
        "the PLC refused calls again right after a new login: another client may log in as "
        f"the same PLC user (it said: {err.words})"
    )


def stop_error(err_words: str, var: str | None = None) -> PlcWriteRefusedError:
    """Return the STOP refusal of a write (manual 9.1 d), with the PLC's own words."""
    lead = f"{var}: " if var else ""
    return PlcWriteRefusedError(f"{lead}{STOP_MESSAGE} ({err_words})")


def permission_error(err: RpcError) -> PlcWriteRefusedError:
    """Return the refusal of a write by a user get_permission (manual 7) said may not write."""
    return PlcWriteRefusedError(f"the PLC user has no write permission ({err.words})")


def request_error(err: RpcError, *, write: bool) -> PlcError:
    """Return the error of a request refused with the session working, in the PLC's words."""
    if write:
        return WriteRefused(f"the PLC refused the write ({err.words})")
    return RequestRefused(f"the PLC refused the request ({err.words})")


def node_error(
    code: Any, var: str, message: Any = None, *, write: bool = False, stopped: bool = False
) -> PlcError:
    """Return the exception for a node whose result code is not 0, with the PLC's own words.

    `stopped`: the reply's status block says the CPU is out of RUN, so a refused write node is
    the STOP refusal whatever its code. 3004 is the manual's "Invalid address."; any other code
    is, by structure, the PLC refusing that node: a write it did not take, or a read it could
    not answer (8.3.1, 9.3.1: "If errors exist, nodes shall return the exact reason").
    """
    if write and stopped:
        return stop_error(said(message, code), var)
    if code == INVALID_ADDRESS:
        if message in (None, "", INVALID_ADDRESS_TEXT):  # no echo of the manual's own words
            return PlcAddressError(f"{var}: the PLC has no such address (code {code})")
        return PlcAddressError(f"{var}: the PLC has no such address ({said(message, code)})")
    kind = PlcWriteRefusedError if write else PlcProtocolError
    return kind(f"{var}: the PLC refused it ({said(message, code)})")
