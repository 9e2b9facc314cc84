"""The S7-200 SMART Web API result codes, one table for the whole simulator."""

from __future__ import annotations

# The manual's error page is missing: only 3004 "Invalid address." is the vendor's own (it appears
# in the read and write examples). Every other code here is ours; the client keeps the same table
# in custom_components/plc_bridge/plc/vendors/s7_smart/codec.py.
PARSE_ERROR = -32700
INVALID_REQUEST = -32600
METHOD_NOT_FOUND = -32601
INVALID_PARAMS = -32602
LOGIN_FAILED = 1001
INVALID_TOKEN = 1002
PERMISSION_DENIED = 1003
NOT_IN_RUN = 2001
TOO_MANY_NODES = 2002
PAYLOAD_TOO_LARGE = 2003
INVALID_ADDRESS = 3004
INVALID_MODE = 3005
INVALID_VALUE = 3006
READ_ONLY = 3007
ERRORS: dict[int, str] = {
    PARSE_ERROR: "Parse error.",
    INVALID_REQUEST: "Invalid Request.",
    METHOD_NOT_FOUND: "Method not found.",
    INVALID_PARAMS: "Invalid params.",
    LOGIN_FAILED: "Login failed.",
    INVALID_TOKEN: "Invalid token.",
    PERMISSION_DENIED: "Permission denied.",
    NOT_IN_RUN: "CPU not in RUN.",
    TOO_MANY_NODES: "Too many nodes.",
    PAYLOAD_TOO_LARGE: "Payload too large.",
    INVALID_ADDRESS: "Invalid address.",
    INVALID_MODE: "Invalid mode.",
    INVALID_VALUE: "Invalid value.",
    READ_ONLY: "Read-only address.",
}


FOREIGN: dict[int, int] = {
    code: 7100 + index
    for index, code in enumerate(sorted(ERRORS))
    if code not in (INVALID_ADDRESS, PARSE_ERROR, INVALID_REQUEST, METHOD_NOT_FOUND, INVALID_PARAMS)
}
"""Other codes for every error the manual does not define (3004 is its own; the negative ones
are JSON-RPC 2.0's): a firmware whose table the client cannot know, for `foreign_codes`."""


def shown(code: int, *, foreign: bool) -> tuple[int, str]:
    """Return the code and message a reply carries, in the manual's table or a foreign one."""
    if foreign and code in FOREIGN:
        return FOREIGN[code], f"Request refused (E{FOREIGN[code]})"
    return code, ERRORS[code]


class Fault(Exception):
    """A JSON-RPC error for the whole request, or a result code for one node."""

    def __init__(self, code: int) -> None:
        super().__init__(ERRORS[code])
        self.code = code
