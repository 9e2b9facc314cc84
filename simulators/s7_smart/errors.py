"""The S7-200 SMART Web API result codes, one table for the whole simulator."""

from __future__ import annotations

# The manual's error page is missing: only 3004 "Invalid address." is the vendor's own (it appears
# in the read and write examples). Every other code here is ours: the `codes` switch answers with
# this table, a foreign one, or this one's codes given other meanings (READINGS.md).
PARSE_ERROR = -32700
INVALID_REQUEST = -32600
METHOD_NOT_FOUND = -32601
INVALID_PARAMS = -32602
INTERNAL_ERROR = -32603
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
    INTERNAL_ERROR: "Internal error.",
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


_JSON_RPC = (PARSE_ERROR, INVALID_REQUEST, METHOD_NOT_FOUND, INVALID_PARAMS, INTERNAL_ERROR)
FOREIGN: dict[int, int] = {
    code: 7100 + index
    for index, code in enumerate(sorted(ERRORS))
    if code not in (INVALID_ADDRESS, *_JSON_RPC)
}
"""Other codes for every error the manual does not define (3004 is its own; the negative ones
are JSON-RPC 2.0's): a firmware whose table the client cannot know, for `codes="foreign"`."""

SHUFFLED: dict[int, tuple[int, str]] = {
    LOGIN_FAILED: (3005, "Wrong user name or password"),
    INVALID_TOKEN: (2002, "Session expired, please login"),
    PERMISSION_DENIED: (3007, "No write permission"),
    NOT_IN_RUN: (3006, "CPU is not in RUN mode"),
    TOO_MANY_NODES: (INVALID_TOKEN, "Too many nodes."),
    PAYLOAD_TOO_LARGE: (2001, "Payload too large"),
    INVALID_MODE: (1003, "Data type not supported for this address"),
    INVALID_VALUE: (1001, "Value out of range"),
    READ_ONLY: (INVALID_MODE, "Address is read only"),
}
"""The same codes meaning other things, in a firmware's own words, for `codes="shuffled"`: a
client that took a code for its meaning in our table would be wrong every time."""

CODES = ("guessed", "foreign", "shuffled")


def shown(code: int, codes: str = "guessed") -> tuple[int, str]:
    """Return the code and message a reply carries, in the table the `codes` switch names."""
    if codes == "foreign" and code in FOREIGN:
        return FOREIGN[code], f"Request refused (E{FOREIGN[code]})"
    if codes == "shuffled" and code in SHUFFLED:
        return SHUFFLED[code]
    return code, ERRORS[code]


class Fault(Exception):
    """A JSON-RPC error for the whole request, or a result code for one node."""

    def __init__(self, code: int) -> None:
        super().__init__(ERRORS[code])
        self.code = code
