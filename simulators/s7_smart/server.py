"""A Siemens S7-200 SMART Web API simulator: JSON-RPC 2.0 on POST /Web_api over HTTPS.

It follows the vendor's Web API manual (../shared/specs/siemens-s7-200-smart-web-api.txt):
sha512 logins with a cookie token that a newer login of the same user replaces, idle expiry,
32 nodes and 15 KB per request, no JSON-RPC batches, writes only in RUN, per-node result codes.
"""

from __future__ import annotations

import base64
from collections import Counter
from collections.abc import Callable
import contextlib
from datetime import datetime
import hashlib
import json
import math
import secrets
import time
from typing import Any, NamedTuple

from aiohttp import web

from ..base import HttpSimulator
from .errors import (
    CODES,
    INVALID_ADDRESS,
    INVALID_PARAMS,
    INVALID_REQUEST,
    INVALID_TOKEN,
    INVALID_VALUE,
    LOGIN_FAILED,
    METHOD_NOT_FOUND,
    NOT_IN_RUN,
    PARSE_ERROR,
    PAYLOAD_TOO_LARGE,
    PERMISSION_DENIED,
    READ_ONLY,
    TOO_MANY_NODES,
    Fault,
    shown,
)
from .memory import DATE_FORMAT, READ_ONLY_SM, REAL_FORMATS, Memory, Value, printed_real

DEFAULT_USER = "admin"
DEFAULT_PASSWORD = "Smart-200"
API_VERSION = "1.0.0"
API_LIST = ["login", "logout", "get_permission", "read", "write", "browse"]
PAYLOAD_LIMIT = 15 * 1024
MAX_NODES = 32
MAX_USERS = 4
STRINGS = ("escaped", "utf-8", "raw", "latin-1", "gbk", "gbk-declared")
"""How a firmware puts a string's bytes into a reply (READINGS.md row 17): each byte as the
character of its number, escaped (\u00b0) or in UTF-8; the bytes as they are, undeclared or
declared ISO 8859-1; the bytes read as GBK text, sent in UTF-8 or as they are, declared GBK."""


class HttpFault(NamedTuple):
    """An HTTP answer given instead of handling one request (a busy server, a proxy)."""

    status: int
    body: str = ""
    headers: dict[str, str] = {}  # noqa: RUF012 - never changed, only read


class S7SmartSimulator(HttpSimulator):
    """An S7-200 SMART CPU (V memory of an ST60/SR60) with its Web API.

    Knobs for tests: `mode` ("RUN"/"STOP"), `malformed`, `write_permission`, `idle_timeout`,
    `v_size` (a CPU with less V memory), `rewrite` (edit every successful reply before it is
    sent), `system_status`, `forced`, `clock` (stands still unless set, so tests stay
    deterministic), `http_faults` (HTTP answers given instead of the next requests'). Where the
    manual is silent, a switch per reading (READINGS.md): `codes`, `stop_refusal`, `max_nodes`
    with `node_limit_error`, `max_write_nodes`, `error_status`, `cookie_name_in_token`, `version`,
    `strings` (how a string's bytes go into a reply), `real_format` (how a REAL is printed),
    `busy` with `busy_status` (busy answers in a row). `arrivals` keeps when each request came.
    """

    tls = True
    common_name = "s7-200-smart"

    def __init__(
        self,
        users: dict[str, str] | None = None,
        *,
        idle_timeout: float = 1800.0,
        write_permission: bool = True,
    ) -> None:
        super().__init__()
        users = {DEFAULT_USER: DEFAULT_PASSWORD} if users is None else users
        if len(users) > MAX_USERS:
            raise ValueError(f"an S7-200 SMART has at most {MAX_USERS} Web server users")
        self._hashes = {user: hashlib.sha512(pw.encode()).hexdigest() for user, pw in users.items()}
        self._sessions: dict[str, tuple[str, float]] = {}  # token -> (user, last use)
        self.idle_timeout = idle_timeout
        self.write_permission = write_permission
        self.mode = "RUN"
        self.malformed = False
        self.system_status = "OK"
        # The manual defines 3004 only: "guessed" answers with our table, "foreign" with codes
        # and words no client knows, "shuffled" with our codes meaning other things.
        self.codes = "guessed"
        self.stop_refusal = "request"  # or "node": each node of a write in STOP is refused
        self.max_nodes = MAX_NODES  # a firmware may take fewer nodes a request than the manual
        self.node_limit_error = TOO_MANY_NODES  # the whole-request error past max_nodes
        # A firmware refusing writes of more nodes for another reason than their count (reads
        # of as many pass): the write's payload, say. None: writes take what reads take.
        self.max_write_nodes: int | None = None
        self.error_status = 200  # the HTTP status of an error reply (JSON-RPC over HTTP: 500)
        self.version = API_VERSION  # the manual's reply shows "${version_string}." (10.3.1)
        self.http_faults: list[HttpFault] = []
        self.forced = False
        self.cookie_name_in_token = True
        self.strings = "escaped"  # STRINGS: how the bytes of a string go into a reply
        self.real_format = "shortest"  # REAL_FORMATS: how a REAL is printed in a reply
        self.busy = 0  # the next requests answered busy (busy_status, no JSON-RPC), in a row
        self.busy_status = HttpFault(503, "<html>Server busy</html>")
        self.arrivals: list[float] = []  # time.monotonic() of each request, busy ones too
        self.rewrite: Callable[[dict[str, Any]], dict[str, Any]] | None = None
        self.calls: Counter[str] = Counter()
        self.memory = Memory()

    @property
    def clock(self) -> datetime:
        """The PLC clock (naive local time); DATE reads it, DATE writes set it."""
        return self.memory.clock

    @clock.setter
    def clock(self, value: datetime) -> None:
        self.memory.clock = value

    @property
    def v_size(self) -> int:
        """Bytes of V memory (20480 as an ST60/SR60; set less to act as a smaller CPU)."""
        return self.memory.v_size

    @v_size.setter
    def v_size(self, value: int) -> None:
        self.memory.v_size = value

    def build_app(self, app: web.Application) -> None:
        app.router.add_post("/Web_api", self._handle)

    # -- the test-facing API ---------------------------------------------------------------

    def set(self, address: str, value: Value, mode: str = "signed") -> None:
        """Store a value as the PLC would encode it (no RUN or read-only check)."""
        if address.strip().upper() == "DATE" and isinstance(value, datetime):
            self.clock = value.replace(microsecond=0, tzinfo=None)
            return
        try:
            self.memory.store(self.memory.locate(address, mode), value)
        except Fault as fault:
            raise ValueError(f"{address}: {fault}") from None

    def put_string(self, address: str, data: bytes) -> None:
        """Put a string of any bytes at a VB address, as the user program does (`25°C`)."""
        where = self.memory.locate(address, "string")
        if where.area != "V":
            raise ValueError(f"{address}: the program's strings go to V memory here")
        self.memory.put_string(where.offset, data)

    def get(self, address: str, mode: str = "signed") -> Value:
        """Return a stored value as the PLC reports it (bits as bool, DATE as datetime)."""
        try:
            where = self.memory.locate(address, mode)
        except Fault as fault:
            raise ValueError(f"{address}: {fault}") from None
        if where.area == "DATE":
            return self.clock
        value = self.memory.load(where)
        return bool(value) if where.bit is not None else value

    def animate(self, elapsed: float) -> None:
        """The demo's process: a tank temperature (VD100) drifts, a counter (VW10) counts.

        The boiler's water (VW50, tenths of a degree) drifts too and raises Overheat (bit 0 of
        VW70) above a set point (VW52), the pump's contactor (V63.0) follows its command
        (V61.1), and the shutter's open (V60.0) and close (V60.1) commands reach their limit
        switches (V62.0, V62.1): scripts/develop's machines.
        """
        self.set("VD100", round(21.5 + 1.5 * math.sin(2 * math.pi * elapsed / 900), 1), "float")
        self.set("VW10", int(elapsed) % 32768)
        water = round(550 + 50 * math.sin(2 * math.pi * elapsed / 600))
        self.set("VW50", water)
        target = int(self.get("VW52"))
        self.set("VW70", int(self.get("VW70")) & ~1 | int(0 < target < water))
        self.set("V63.0", self.get("V61.1"))
        opening, closing = self.get("V60.0"), self.get("V60.1")
        if opening != closing:
            self.set("V62.0", opening)
            self.set("V62.1", closing)

    def invalidate_tokens(self) -> None:
        """Drop every token, as if another client had logged in with each online user."""
        now = time.monotonic()
        self._sessions = {self._token(user): (user, now) for user, _ in self._sessions.values()}

    # -- HTTP and JSON-RPC -----------------------------------------------------------------

    async def _handle(self, request: web.Request) -> web.StreamResponse:
        """Answer one JSON-RPC call (never a batch)."""
        self.arrivals.append(time.monotonic())
        if self.busy > 0:
            self.busy -= 1
            fault = self.busy_status
            return web.Response(status=fault.status, text=fault.body, headers=fault.headers)
        if self.http_faults:
            fault = self.http_faults.pop(0)
            return web.Response(status=fault.status, text=fault.body, headers=fault.headers)
        if self.codes not in CODES:
            raise ValueError(f"codes must be one of {CODES}")
        if self.strings not in STRINGS or self.real_format not in REAL_FORMATS:
            raise ValueError(f"strings: one of {STRINGS}; real_format: one of {REAL_FORMATS}")
        if request.content_type != "application/json":
            return self._error(None, INVALID_REQUEST)
        body = await request.read()
        if len(body) > PAYLOAD_LIMIT:
            return self._error(None, PAYLOAD_TOO_LARGE)
        try:
            message = json.loads(body.decode("utf-8"))
        except ValueError:
            return self._error(None, PARSE_ERROR)
        if not isinstance(message, dict):  # a list is a batch: "not supported" (manual 4.4)
            return self._error(None, INVALID_REQUEST)
        call_id, method = message.get("id"), message.get("method")
        if message.get("jsonrpc") != "2.0" or "id" not in message or not isinstance(method, str):
            return self._error(call_id, INVALID_REQUEST)
        self.calls[method] += 1
        handler = self._methods().get(method)
        if handler is None:
            return self._error(call_id, METHOD_NOT_FOUND)
        try:
            result = handler(request, message.get("params"))
        except Fault as fault:
            return self._error(call_id, fault.code)
        if self.malformed and method in ("read", "write"):
            return web.Response(text='{"jsonrpc":"2.0","id":', content_type="application/json")
        reply = {"jsonrpc": "2.0", "id": call_id, "result": result}
        if self.rewrite is not None:
            reply = self.rewrite(reply)
        return self._reply(reply)

    def _reply(self, reply: dict[str, Any]) -> web.Response:
        """Return a successful reply with its strings' bytes put in as `strings` says."""
        if self.strings == "escaped":
            return web.json_response(reply, dumps=_compact)
        text = json.dumps(reply, separators=(",", ":"), ensure_ascii=False)
        charset = {"latin-1": "iso-8859-1", "gbk-declared": "gbk"}.get(self.strings)
        body = text.encode("utf-8" if self.strings in ("utf-8", "gbk") else "latin-1")
        content_type = "application/json" + (f"; charset={charset}" if charset else "")
        return web.Response(body=body, headers={"Content-Type": content_type})

    def _error(self, call_id: Any, code: int) -> web.Response:
        """Return a JSON-RPC error reply, in the code table and HTTP status the switches name."""
        code, message = shown(code, self.codes)
        error = {"code": code, "message": message}
        return web.json_response(
            {"jsonrpc": "2.0", "id": call_id, "error": error},
            status=self.error_status,
            dumps=_compact,
        )

    def _methods(self) -> dict[str, Callable[[web.Request, Any], dict[str, Any]]]:
        """Map each API method to its handler."""
        return {
            "login": self._login,
            "logout": self._logout,
            "get_permission": self._get_permission,
            "read": self._read,
            "write": self._write,
            "browse": self._browse,
        }

    def _token(self, user: str) -> str:
        """Return a new token; like the device's, it is base64 of the user name and random bytes."""
        return base64.b64encode(f"{user}.".encode() + secrets.token_bytes(16)).decode()

    def _login(self, request: web.Request, params: Any) -> dict[str, Any]:
        if not isinstance(params, dict):
            raise Fault(INVALID_PARAMS)
        user, password = params.get("username"), params.get("password")
        if not isinstance(user, str) or not isinstance(password, str):
            raise Fault(INVALID_PARAMS)
        if user not in self._hashes or password.lower() != self._hashes[user]:
            raise Fault(LOGIN_FAILED)
        self._sessions = {t: s for t, s in self._sessions.items() if s[0] != user}
        token = self._token(user)
        self._sessions[token] = (user, time.monotonic())
        cookie = f"Session-Id={token}" if self.cookie_name_in_token else token
        return {"code": 0, "message": "Success.", "cookie": cookie}

    def _session(self, request: web.Request) -> str:
        """Return the user of the request's token, or refuse a missing or expired token."""
        token = None
        for part in request.headers.get("Cookie", "").split(";"):
            name, _, value = part.strip().partition("=")
            if name == "Session-Id":
                token = value
        now = time.monotonic()
        session = self._sessions.get(token or "")
        if session is None or now - session[1] > self.idle_timeout:
            self._sessions.pop(token or "", None)
            raise Fault(INVALID_TOKEN)
        self._sessions[token or ""] = (session[0], now)
        return session[0]

    def _logout(self, request: web.Request, params: Any) -> dict[str, Any]:
        with contextlib.suppress(Fault):  # logging out a user not online succeeds (manual 6.1)
            self._session(request)
        for part in request.headers.get("Cookie", "").split(";"):
            self._sessions.pop(part.strip().partition("=")[2], None)
        return {"code": 0, "message": "Success."}

    def _get_permission(self, request: web.Request, params: Any) -> dict[str, Any]:
        self._session(request)
        return {"code": 0, "message": "Success.", "permission": {"write": self.write_permission}}

    def _browse(self, request: web.Request, params: Any) -> dict[str, Any]:
        return {"code": 0, "message": "Success.", "version": self.version, "api": API_LIST}

    def _status(self) -> dict[str, str]:
        """Return the status block of read and write replies."""
        return {
            "Date": self.clock.strftime(DATE_FORMAT),
            "Operating Mode": self.mode,
            "System Status": self.system_status,
            "Force Status": "Forced" if self.forced else "Not Forced",
        }

    def _nodes(self, params: Any) -> list[Any]:
        """Return the nodes of a read or write; an empty or null list asks for the status only."""
        if params is None:
            return []
        if not isinstance(params, list):
            raise Fault(INVALID_PARAMS)
        if len(params) > self.max_nodes:
            raise Fault(self.node_limit_error)
        return params

    def _read(self, request: web.Request, params: Any) -> dict[str, Any]:
        self._session(request)
        nodes = self._nodes(params)
        return {"status": self._status(), "data": [self._node(n, False) for n in nodes]}

    def _write(self, request: web.Request, params: Any) -> dict[str, Any]:
        self._session(request)
        if not self.write_permission:
            raise Fault(PERMISSION_DENIED)
        nodes = self._nodes(params)
        if self.max_write_nodes is not None and len(nodes) > self.max_write_nodes:
            raise Fault(self.node_limit_error)
        if nodes and self.mode != "RUN" and self.stop_refusal == "request":
            raise Fault(NOT_IN_RUN)
        return {"status": self._status(), "data": [self._node(n, True) for n in nodes]}

    def _node(self, node: Any, write: bool) -> dict[str, Any]:
        """Read or write one node; its failure is reported in the node only."""
        var = node.get("var") if isinstance(node, dict) else None
        try:
            if not isinstance(node, dict) or node.get("type", "address") != "address":
                raise Fault(INVALID_PARAMS)
            if not isinstance(var, str):
                raise Fault(INVALID_ADDRESS)
            where = self.memory.locate(var, node.get("mode", "signed"))
            if write:
                if self.mode != "RUN":  # stop_refusal "node": the request passed, no node does
                    raise Fault(NOT_IN_RUN)
                if "value" not in node:
                    raise Fault(INVALID_VALUE)
                if where.area == "SM" and where.offset < READ_ONLY_SM:
                    raise Fault(READ_ONLY)
                self.memory.store(where, node["value"])
            else:
                value = self._printed(where.mode, self.memory.load(where))
        except Fault as fault:
            code, message = shown(fault.code, self.codes)
            return {"code": code, "message": message, "var": var}
        done = {"code": 0, "message": "Success.", "var": var}
        return done if write else done | {"value": value}

    def _printed(self, mode: str, value: Any) -> Any:
        """Return a read value as this firmware prints it (`real_format`, `strings`)."""
        if mode == "float" and self.real_format != "shortest":
            return printed_real(value, self.real_format)
        if mode == "string" and self.strings == "gbk":
            return value.encode("latin-1").decode("gbk", errors="replace")
        return value


def _compact(value: Any) -> str:
    """Serialize JSON without spaces, as the device does."""
    return json.dumps(value, separators=(",", ":"))
