"""The S7-200 SMART Web API client: JSON-RPC 2.0 on POST https://host/Web_api."""

from __future__ import annotations

import asyncio
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from datetime import datetime
import hashlib
import logging
from typing import Any, ClassVar
from zoneinfo import ZoneInfo

import aiohttp

from ...client import PlcClient
from ...errors import PlcError, PlcProtocolError
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
    MAX_NODES,
    Node,
    check_value,
    decode,
    decode_status,
    encode,
    node_for,
    plan,
    read_plan,
    reply_nodes,
)
from .errors import (
    RequestRefused,
    RpcError,
    login_error,
    node_error,
    permission_error,
    request_error,
    session_error,
    stop_error,
)
from .rpc import WebApi

_LOGGER = logging.getLogger(__name__)

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


@dataclass(frozen=True, slots=True)
class _PollPlan:
    """A poll parsed and grouped once: kept while the same points are polled again."""

    key: tuple[tuple[Point, ...], int]  # the points, and the node limit they were planned for
    invalid: dict[Point, PointResult]
    wanted: dict[Node, list[Point]]
    groups: list[tuple[list[Node], list[dict[str, Any]]]]


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
        self._api: WebApi | None = None
        self._token: str | None = None
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
        """The memory area and bits a point covers (VW100 and VB101 overlap; V60.0, V60.2 not).

        Counted in bits: a write names a bit by its own address (§9.2: `V7000.0`), so a bit
        beside a read-only bit of the same byte stays writable.
        """
        node = node_for(point)
        area, start, end = covered(node.address, node.kind)
        if node.address.bit is not None:
            first = start * 8 + node.address.bit
            return Footprint(area, first, first + 1)
        return Footprint(area, start * 8, end * 8)

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

    async def _send(self, method: str, params: Any) -> dict[str, Any]:
        """Send one call with the token held; return its result, raise RpcError for a refusal."""
        if self._api is None:
            self._api = WebApi(self._http())
        return await self._api.call(method, params, self._token)

    async def connect(self) -> DeviceInfo:
        """Ask the API version, log in and ask the user's write permission."""
        browse = await self._send("browse", None)
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
            replies: list[dict[str, Any]] = []
            try:
                for _group, params in planned.groups:
                    replies.append(await self._call("read", params))
                break
            except RequestRefused:
                if not await self._fewer_nodes(planned.groups[len(replies)][1]):
                    raise
        values = dict(planned.invalid)
        status = PlcStatus()
        for (group, _params), result in zip(planned.groups, replies, strict=True):
            status = decode_status(result.get("status"), self._zone)
            for node, item in zip(group, reply_nodes(result, group), strict=True):
                outcome = self._outcome(node, item)
                for point in planned.wanted[node]:
                    values[point] = outcome
        return ReadResult(values=values, status=status)

    async def _fewer_nodes(self, params: list[dict[str, Any]]) -> bool:
        """Learn how many nodes a read may hold, after the PLC refused these whole; False if none.

        Reached with the session working (an empty read passed after a fresh login): perhaps a
        firmware taking fewer nodes than the manual's 32 (8.1 c), whatever code or words it
        refuses with. Halve until a read passes, then bisect up to the most that pass; the
        limit is kept for later polls and writes.
        """
        taken, refused = 0, len(params)
        while (size := (taken + refused) // 2 if taken else refused // 2) > taken:
            try:
                self._noted(await self._send("read", params[:size]))
                taken = size
            except RpcError:
                refused = size
        if not taken:
            return False
        self._max_nodes = taken
        _LOGGER.info(
            "%s refused %d nodes in one read; reading at most %d from now on",
            self.config.host,
            len(params),
            taken,
        )
        return True

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
        for group in plan(items, wire, self._max_nodes):
            result = await self._call("write", [wire(item) for item in group])
            stopped = self._mode not in (None, "RUN")  # this reply's status block (9.3.1)
            nodes = [node for node, _point, _value in group]
            for (node, point, value), data in zip(group, reply_nodes(result, nodes), strict=True):
                code = data.get("code")
                error = (
                    node_error(
                        code, node.address.text, data.get("message"), write=True, stopped=stopped
                    )
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
                    await self._send("logout", None)
            except (PlcError, RpcError, TimeoutError) as err:
                _LOGGER.debug("Logout from %s failed: %s", self.config.host, err)
        self._token = None
        self._transport = None
        self._api = None
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
                result = await self._send("login", params)
            except RpcError as err:
                raise login_error(err) from None
            cookie = result.get("cookie")
            if not isinstance(cookie, str) or not cookie:
                raise PlcProtocolError("the PLC accepted the login but sent no token")
            self._token = cookie
            self._logins += 1

    async def _call(self, method: str, params: Any) -> dict[str, Any]:
        """Call a method that needs a login; after a refusal log in once and retry once.

        The manual defines no session error code (its error page is missing), only that a
        request needs a login first (7.1 a, 8.1 a, 9.1 a) and that a token ends with another
        login or half an hour idle (5.1 b, 5.1 c). So what a refusal means is told by
        structure, never by its code: an empty read (8.1 d) that passes shows the session
        works; its status block tells STOP (9.1 d); get_permission (7) told whether the user
        may write. A refused write with the session working is not sent again; any other
        refusal is taken as a lost session: one fresh login, one retry. A renewal is counted
        when a call with the new token passes where the old one's was refused.
        """
        if self._token is None:
            await self._login(self._logins)  # callers at once share the one login
        seen = self._logins
        write = method == "write"
        try:
            return self._noted(await self._send(method, params))
        except RpcError as err:
            # Another caller's login since then would make the empty read pass on its token.
            if write and self._logins == seen and await self._session_works():
                raise self._write_refused(err) from None
        await self._login(seen)
        try:
            result = self._noted(await self._send(method, params))
        except RpcError as err:
            if not await self._session_works():
                raise session_error(err) from None
            if write:
                self.metrics.session_renewals += 1  # the status read passed, the old one not
                raise self._write_refused(err) from None
            raise request_error(err, write=False) from None
        self.metrics.session_renewals += 1
        return result

    def _write_refused(self, err: RpcError) -> PlcError:
        """Return the error of a write refused whole while the session works."""
        if self._mode not in (None, "RUN"):
            return stop_error(err.words)
        if not self._can_write:
            return permission_error(err)
        return request_error(err, write=True)

    async def _session_works(self) -> bool:
        """Send an empty read (manual 8.1 d): say whether it passed, and note its status."""
        try:
            self._noted(await self._send("read", []))
        except RpcError:
            return False
        return True

    def _noted(self, result: dict[str, Any]) -> dict[str, Any]:
        """Remember the operating mode a reply's status block reports (read and write replies)."""
        status = result.get("status")
        if isinstance(status, dict) and isinstance(status.get("Operating Mode"), str):
            self._mode = status["Operating Mode"].strip().upper()
        return result
