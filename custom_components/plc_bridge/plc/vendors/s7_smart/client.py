"""The S7-200 SMART Web API client: JSON-RPC 2.0 on POST https://host/Web_api."""

from __future__ import annotations

import asyncio
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from datetime import datetime
import hashlib
import itertools
import json
import logging
from typing import Any, ClassVar
from zoneinfo import ZoneInfo

import aiohttp

from ...client import PlcClient
from ...errors import (
    PlcAuthenticationError,
    PlcConnectionError,
    PlcError,
    PlcProtocolError,
    PlcWriteRefusedError,
)
from ...http import HttpTransport
from ...types import (
    ConnectionConfig,
    DeviceInfo,
    Footprint,
    PlcStatus,
    Point,
    PointResult,
    ReadResult,
    TlsMode,
    Value,
    ValueKind,
)
from .address import BOOL, DATE, MODES, covered, writable
from .codec import (
    INVALID_TOKEN,
    MAX_NODES,
    STOP_MESSAGE,
    Node,
    RequestRefused,
    check_value,
    decode,
    decode_status,
    dumps,
    encode,
    node_error,
    node_for,
    plan,
    read_plan,
    reply_nodes,
    request_error,
)

_LOGGER = logging.getLogger(__name__)

PATH = "/Web_api"
LOGOUT_TIMEOUT = 2.0
_DATE_POINT = Point("DATE", "signed")
_KINDS = {
    BOOL: ValueKind.BOOL,
    DATE: ValueKind.DATETIME,
    "signed": ValueKind.INTEGER,
    "unsigned": ValueKind.INTEGER,
    "float": ValueKind.FLOAT,
    "string": ValueKind.TEXT,
    "raw": ValueKind.BYTES,
}


def cookie_header(token: str) -> str:
    """Return the Cookie header for a login token.

    The manual's examples send "Session-Id=<base64>" (curl -b), but do not say whether login
    returns the pair or the bare token. A name=value pair is sent as given; a bare token (whose
    base64 padding may end in "=") gets the name the examples show.
    """
    return token if "=" in token.rstrip("=") else f"Session-Id={token}"


@dataclass(frozen=True, slots=True)
class _PollPlan:
    """A poll parsed and grouped once: kept while the same points are polled again."""

    key: tuple[tuple[Point, ...], int]  # the points, and the node limit they were planned for
    invalid: dict[Point, PointResult]
    wanted: dict[Node, list[Point]]
    groups: list[tuple[list[Node], list[dict[str, Any]]]]


READING = frozenset({"browse", "login", "get_permission", "read"})
"""Methods sent again once when a kept-alive connection breaks before the answer: they change
nothing in the CPU (a login sent twice leaves the second token, the one kept)."""


class _RpcError(Exception):
    """An error answer; `_call` turns it into a PlcError and never lets it out."""

    def __init__(self, code: int, message: str) -> None:
        super().__init__(code, message)
        self.code = code
        self.message = message


def plc_words(err: _RpcError) -> str:
    """Return what the PLC said about a refusal: its message and its code."""
    return f"{err.message or 'no message'}, code {err.code}"


class S7SmartClient(PlcClient):
    """A Siemens S7-200 SMART CPU (firmware 2.7 or later) through its Web API."""

    vendor: ClassVar[str] = "s7_smart"
    default_port: ClassVar[int] = 443
    default_tls: ClassVar[TlsMode] = TlsMode.PIN
    tls_modes: ClassVar[tuple[TlsMode, ...]] = (TlsMode.PIN, TlsMode.VERIFY, TlsMode.OFF)
    needs_credentials: ClassVar[bool] = True
    data_types: ClassVar[tuple[str, ...]] = MODES
    default_scan_interval: ClassVar[float] = 10.0
    max_points_per_request: ClassVar[int] = MAX_NODES
    request_interval: ClassVar[float] = 1.0  # "call less than once a second" (manual 4.2)

    def __init__(
        self, config: ConnectionConfig, session: aiohttp.ClientSession | None = None
    ) -> None:
        """Keep the settings; the transport is made and the login done in `connect`."""
        super().__init__(config, session)
        self._transport: HttpTransport | None = None
        self._token: str | None = None
        self._ids = itertools.count(1)
        self._zone = ZoneInfo(self.config.time_zone)
        self._plan: _PollPlan | None = None
        self._login_lock = asyncio.Lock()
        self._logins = 0  # successful logins so far: concurrent callers share one
        self._mode: str | None = None  # the operating mode the last status block reported
        self._can_write = True  # what get_permission said at connect (manual 7)
        self._max_nodes = MAX_NODES  # lowered, and kept, when the PLC refuses as many

    @classmethod
    def validate_point(cls, point: Point) -> Point:
        """Return the point with its address in upper case; raise PlcAddressError."""
        node = node_for(point)
        return Point(node.address.text, point.data_type.strip().lower())

    @classmethod
    def footprint(cls, point: Point) -> Footprint:
        """The memory area and bytes a point covers (VW100 and VB101 overlap)."""
        node = node_for(point)
        return Footprint(*covered(node.address, node.kind))

    @classmethod
    def address_writable(cls, point: Point) -> bool:
        """False for inputs (I, AIW), high-speed counters and the read-only SM bytes."""
        node = node_for(point)
        return writable(node.address, node.kind)

    @classmethod
    def validate_value(cls, point: Point, value: Value) -> Value:
        """Return the value checked for the point's address and mode; raise PlcValueError."""
        node = node_for(point)
        return check_value(node.address, node.kind, value)

    @classmethod
    def value_kind(cls, point: Point) -> ValueKind:
        """Return what the point holds: a bit is a BOOL and DATE the clock, whatever the mode."""
        return _KINDS[node_for(point).kind]

    @classmethod
    def requests_for(cls, points: Sequence[Point]) -> int:
        """Count the requests of one poll: distinct valid points, 32 and 15 KB a request."""
        nodes: dict[Node, None] = {}
        for point in points:
            try:
                nodes[node_for(point)] = None
            except PlcError:
                continue
        return len(read_plan(list(nodes)))

    def _http(self) -> HttpTransport:
        """Return the transport, made on first use."""
        if self._transport is None:
            self._transport = HttpTransport(
                self.config, self.session, self.metrics, request_interval=self.request_interval
            )
        return self._transport

    async def connect(self) -> DeviceInfo:
        """Ask the API version, log in and ask the user's write permission."""
        browse = await self._rpc("browse", None)
        version = str(browse.get("version", "")).strip().rstrip(".")  # the manual shows "x.y.z."
        await self._login()
        permission = (await self._call("get_permission", None)).get("permission")
        can_write = isinstance(permission, dict) and permission.get("write") is True
        self._can_write = can_write
        return DeviceInfo(
            vendor=self.vendor,
            model="S7-200 SMART",
            serial=None,  # the Web API reports no serial number
            firmware=f"Web API {version}" if version else None,
            can_write=can_write,
        )

    def _poll_plan(self, points: Sequence[Point], *, keep: bool = True) -> _PollPlan:
        """Return the parsed and grouped poll, reused while the polled points stay the same.

        An on-demand read (`keep` false) is planned on its own and leaves the poll's plan.
        """
        key = (tuple(points), self._max_nodes)
        if not keep or self._plan is None or self._plan.key != key:
            invalid: dict[Point, PointResult] = {}
            wanted: dict[Node, list[Point]] = {}
            for point in points:
                try:
                    wanted.setdefault(node_for(point), []).append(point)
                except PlcError as err:
                    invalid[point] = PointResult(error=err)
            groups = [
                (group, [node.request() for node in group])
                for group in read_plan(list(wanted), self._max_nodes)
            ]
            planned = _PollPlan(key, invalid, wanted, groups)
            if not keep:
                return planned
            self._plan = planned
        return self._plan

    async def _read(self, points: Sequence[Point], *, poll: bool) -> ReadResult:
        """Read every distinct point once, 32 nodes a request; status from the last reply."""
        while True:
            planned = self._poll_plan(points, keep=poll)
            try:
                replies = [await self._call("read", params) for _group, params in planned.groups]
                break
            except RequestRefused:
                largest = max(len(group) for group, _params in planned.groups)
                if largest <= 1:
                    raise
                # Refused even after a fresh login: perhaps a firmware taking fewer nodes than
                # the manual's 32 (8.1). Halve, and keep the smaller limit for later polls.
                self._max_nodes = largest // 2
                _LOGGER.info(
                    "%s refused %d nodes in one read; reading at most %d from now on",
                    self.config.host,
                    largest,
                    self._max_nodes,
                )
        values = dict(planned.invalid)
        status = PlcStatus()
        for (group, _params), result in zip(planned.groups, replies, strict=True):
            status = decode_status(result.get("status"), self._zone)
            for node, item in zip(group, reply_nodes(result, group), strict=True):
                outcome = self._outcome(node, item)
                for point in planned.wanted[node]:
                    values[point] = outcome
        return ReadResult(values=values, status=status)

    def _outcome(self, node: Node, item: dict[str, Any]) -> PointResult:
        """Return the result of one read node: its value or its own error."""
        code = item.get("code")
        if code != 0:
            return PointResult(error=node_error(code, node.address.text, item.get("message")))
        try:
            return PointResult(value=decode(node.address, node.kind, item.get("value"), self._zone))
        except PlcProtocolError as err:
            return PointResult(error=err)

    async def _write(self, values: Mapping[Point, Value]) -> dict[Point, PointResult]:
        """Write the values, 32 nodes a request; a node's failure stays in its own result."""
        items = [(node_for(point), point, value) for point, value in values.items()]

        def wire(item: tuple[Node, Point, Value]) -> dict[str, Any]:
            return item[0].request(encode(item[0].kind, item[2], self._zone), write=True)

        results: dict[Point, PointResult] = {}
        for group in plan(items, wire):
            result = await self._call("write", [wire(item) for item in group])
            nodes = [node for node, _point, _value in group]
            for (node, point, value), data in zip(group, reply_nodes(result, nodes), strict=True):
                code = data.get("code")
                error = (
                    node_error(code, node.address.text, data.get("message"), write=True)
                    if code != 0
                    else None
                )
                results[point] = PointResult(value=None if error else value, error=error)
        return results

    async def read_clock(self) -> datetime:
        """Return the PLC clock (its DATE address) in the configured time zone."""
        result = (await self._read([_DATE_POINT], poll=False)).values[_DATE_POINT]
        if result.error is not None:
            raise result.error
        assert isinstance(result.value, datetime)
        return result.value

    async def set_clock(self, when: datetime) -> None:
        """Set the PLC clock through its DATE address (the PLC must be in RUN)."""
        error = (await self.write({_DATE_POINT: when}))[_DATE_POINT].error
        if error is not None:
            raise error

    async def close(self) -> None:
        """Log out (a failure is of no consequence) and release the client's own session."""
        if self._transport is not None and self._token is not None:
            try:
                # Short: an unreachable PLC must not hold up Home Assistant's unload or shutdown.
                async with asyncio.timeout(LOGOUT_TIMEOUT):
                    await self._rpc("logout", None)
            except (PlcError, _RpcError, TimeoutError) as err:
                _LOGGER.debug("Logout from %s failed: %s", self.config.host, err)
        self._token = None
        self._transport = None
        await self._close_own_session()

    async def _login(self, seen: int | None = None) -> None:
        """Log in with the password's sha512 hex digest and keep the token.

        Single-flight: a caller that saw `seen` logins before its call failed logs in only if
        nobody has since; concurrent callers share the one new login (a second login would end
        the first's token, manual 5.1 b).
        """
        async with self._login_lock:
            if seen is not None and self._logins != seen and self._token is not None:
                return
            self._token = None
            password = hashlib.sha512(self.config.password.encode()).hexdigest()
            params = {"username": self.config.username, "password": password}
            try:
                result = await self._rpc("login", params)
            except _RpcError as err:
                # Manual 5.3.2: a login fails with an error object, whatever its code says.
                raise PlcAuthenticationError(
                    f"the PLC refused the user name or password ({plc_words(err)})"
                ) from None
            cookie = result.get("cookie")
            if not isinstance(cookie, str) or not cookie:
                raise PlcProtocolError("the PLC accepted the login but sent no token")
            self._token = cookie
            self._logins += 1

    async def _call(self, method: str, params: Any) -> dict[str, Any]:
        """Call a method that needs a login; after any refusal log in once and retry once.

        The manual defines no session error code (its error page is missing), only that a
        request needs a login first (7.1 a, 8.1 a, 9.1 a) and that a token ends with another
        login or half an hour idle (5.1 b, 5.1 c): so a refusal is first taken as a lost
        session. A refused write is first checked against the status an empty read returns
        (8.1 d): out of RUN, it is the STOP refusal ("You can ONLY write data while CPU in run",
        9.1 d), with the PLC's own words; a write refused again after a fresh login, by a user
        get_permission (7) said may not write, is that. Known codes refine the message; they
        never decide the path.
        """
        if self._token is None:
            await self._login(self._logins)  # callers at once share the one login
        seen = self._logins
        try:
            return self._noted(await self._rpc(method, params))
        except _RpcError as err:
            if method == "write" and await self._stopped():
                raise PlcWriteRefusedError(f"{STOP_MESSAGE} ({plc_words(err)})") from None
        self.metrics.session_renewals += 1
        await self._login(seen)
        try:
            return self._noted(await self._rpc(method, params))
        except _RpcError as err:
            if method == "write" and await self._stopped():
                raise PlcWriteRefusedError(f"{STOP_MESSAGE} ({plc_words(err)})") from None
            if method == "write" and not self._can_write:
                raise PlcWriteRefusedError(
                    f"the PLC user has no write permission ({plc_words(err)})"
                ) from None
            if err.code == INVALID_TOKEN:
                # The login just worked: the password is right, another client took the
                # session (the same PLC user logged in elsewhere). Not a case for reauth.
                raise PlcConnectionError(
                    "the PLC dropped the session again right after a new login "
                    "(another client logs in as the same PLC user)"
                ) from None
            raise request_error(err.code, err.message) from None

    async def _stopped(self) -> bool:
        """Ask the status (an empty read, manual 8.1 d) and say whether the CPU is out of RUN."""
        try:
            self._noted(await self._rpc("read", []))
        except (_RpcError, PlcError):
            return False
        return self._mode not in (None, "RUN")

    def _noted(self, result: dict[str, Any]) -> dict[str, Any]:
        """Remember the operating mode a reply's status block reports (read and write replies)."""
        status = result.get("status")
        if isinstance(status, dict) and isinstance(status.get("Operating Mode"), str):
            self._mode = status["Operating Mode"].strip().upper()
        return result

    async def _rpc(self, method: str, params: Any) -> dict[str, Any]:
        """Send one JSON-RPC call (never a batch) and return its result object."""
        call_id = next(self._ids)
        body = dumps({"jsonrpc": "2.0", "method": method, "id": call_id, "params": params})
        headers = {"Content-Type": "application/json"}
        if self._token is not None:
            headers["Cookie"] = cookie_header(self._token)
        status, _headers, raw = await self._http().request(
            "POST", PATH, data=body.encode(), headers=headers, idempotent=method in READING
        )
        try:
            reply = json.loads(raw)
        except ValueError:
            raise PlcProtocolError(
                f"the PLC answered {method} with HTTP {status}, not JSON"
            ) from None
        if not isinstance(reply, dict) or reply.get("jsonrpc") != "2.0":
            raise PlcProtocolError(f"the PLC's answer to {method} is not JSON-RPC 2.0")
        error = reply.get("error")
        # The manual's templates quote the echoed id ("${id_in_requests}"): accept it as text too.
        # An error about the request itself (parse error, too large) may carry a null id.
        if reply.get("id") not in (call_id, str(call_id)) and not (
            reply.get("id") is None and isinstance(error, dict)
        ):
            raise PlcProtocolError(
                f"the PLC answered id {reply.get('id')!r} to request id {call_id} ({method})"
            )
        if isinstance(error, dict):
            code = error.get("code")
            raise _RpcError(code if isinstance(code, int) else 0, str(error.get("message", "")))
        result = reply.get("result")
        if not isinstance(result, dict):
            raise PlcProtocolError(f"the PLC's answer to {method} has no result")
        return result
