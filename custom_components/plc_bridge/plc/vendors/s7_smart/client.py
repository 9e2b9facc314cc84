"""The S7-200 SMART Web API client: JSON-RPC 2.0 on POST https://host/Web_api."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from datetime import datetime
import logging
from typing import Any, ClassVar
from zoneinfo import ZoneInfo

import aiohttp

from ...errors import PlcError, PlcProtocolError
from ...shifting import BYTES
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
from .address import BOOL, DATE, MAX_STRING, MODES, Address, covered, shift, writable
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
from .errors import RequestRefused, RpcError, WriteRefused, node_error
from .session import WebSession

_LOGGER = logging.getLogger(__name__)

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


def _footprint(area: str, start: int, end: int, bit: int | None) -> Footprint:
    """Return the bits a point covers: one bit, or its bytes [start, end)."""
    if bit is not None:
        first = start * 8 + bit
        return Footprint(area, first, first + 1)
    return Footprint(area, start * 8, end * 8)


@dataclass(frozen=True, slots=True)
class _PollPlan:
    """A poll parsed and grouped once: kept while the same points are polled again."""

    key: tuple[tuple[Point, ...], int]  # the points, and the node limit they were planned for
    invalid: dict[Point, PointResult]
    wanted: dict[Node, list[Point]]
    groups: list[tuple[list[Node], list[dict[str, Any]]]]


class S7SmartClient(WebSession):
    """A Siemens S7-200 SMART CPU (firmware 2.7 or later) through its Web API."""

    vendor: ClassVar[str] = "s7_smart"
    default_port: ClassVar[int] = 443
    default_tls: ClassVar[TlsMode] = TlsMode.PIN
    tls_modes: ClassVar[tuple[TlsMode, ...]] = (TlsMode.PIN, TlsMode.VERIFY, TlsMode.OFF)
    needs_credentials: ClassVar[bool] = True
    data_types: ClassVar[tuple[str, ...]] = MODES
    shift_units: ClassVar[tuple[str, ...]] = (BYTES,)
    typed_data_types: ClassVar[bool] = (
        False  # the modes cover every address; a string's length is read
    )
    default_scan_interval: ClassVar[float] = 10.0
    max_points_per_request: ClassVar[int] = MAX_NODES
    request_interval: ClassVar[float] = 1.0  # "call less than once a second" (manual 4.2)

    def __init__(
        self, config: ConnectionConfig, session: aiohttp.ClientSession | None = None
    ) -> None:
        """Keep the settings; the transport is made and the login done in `connect`."""
        super().__init__(config, session)
        self._zone = ZoneInfo(self.config.time_zone)
        self._plan: _PollPlan | None = None
        self._max_nodes = MAX_NODES  # lowered, and kept, when the PLC refuses as many
        self._string_bytes: dict[Address, int] = {}  # the longest each string was read

    @classmethod
    def validate_point(cls, point: Point) -> Point:
        """Return the point with its address in upper case; raise PlcAddressError."""
        node = node_for(point)
        mode = f"string[{node.length}]" if node.length else point.data_type.strip().lower()
        return Point(node.address.text, mode)

    @classmethod
    def shift_point(cls, point: Point, by: int, unit: str, part: str = "") -> Point:
        """Return the point moved by bytes (VB100 + 20 = VB120), checked as `validate_point`."""
        return cls.validate_point(Point(shift(point.address, by, unit), point.data_type))

    @classmethod
    def footprint(cls, point: Point) -> Footprint:
        """The memory area and bits a point covers (VW100 and VB101 overlap; V60.0, V60.2 not).

        Counted in bits: a write names a bit by its own address (§9.2: `V7000.0`), so a bit
        beside a read-only bit of the same byte stays writable. A string covers its declared
        length (`string[20]`), else all a string may hold: only a read tells more (`covers`).
        """
        node = node_for(point)
        return _footprint(*covered(node.address, node.kind, node.length), node.address.bit)

    def covers(self, point: Point) -> Footprint:
        """What a point covers as the PLC has shown it: a string at least its longest read.

        The CPU keeps no string's size, only its length byte: a string read covers that byte
        and the characters read (each beyond ASCII counted as in UTF-8, never fewer bytes than
        the PLC holds), or more where declared; one never read covers what `footprint` says.
        """
        node = node_for(point)
        read = self._string_bytes.get(node.address) if node.kind == "string" else None
        if read is None:
            return self.footprint(point)
        length = max(read, node.length or 0)
        return _footprint(*covered(node.address, node.kind, length), None)

    @classmethod
    def address_writable(cls, point: Point) -> bool:
        """False for inputs (I, AIW), high-speed counters and the read-only SM bytes."""
        node = node_for(point)
        return writable(node.address, node.kind)

    @classmethod
    def validate_value(cls, point: Point, value: Value) -> Value:
        """Return the value checked for the point's address and mode; raise PlcValueError."""
        node = node_for(point)
        return check_value(node.address, node.kind, value, node.length)

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
        """Read every distinct point once, 32 nodes a request; status from the last reply.

        Each request's values are handed on as it returns: a paced poll takes a second each.
        """
        while True:
            planned = self._poll_plan(points, keep=poll)
            values = dict(planned.invalid)
            status = PlcStatus()
            sent = 0
            try:
                for group, params in planned.groups:
                    result = await self._call("read", params)
                    sent += 1
                    status = decode_status(result.get("status"), self._zone)
                    returned: dict[Point, PointResult] = {}
                    for node, item in zip(group, reply_nodes(result, group), strict=True):
                        outcome = self._outcome(node, item)
                        for point in planned.wanted[node]:
                            returned[point] = outcome
                    values |= returned
                    self._request_results(returned)
                break
            except RequestRefused:
                if not await self._fewer_nodes(planned.groups[sent][1]):
                    raise
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
            value = decode(node.address, node.kind, item.get("value"), self._zone)
        except PlcProtocolError as err:
            return PointResult(error=err)
        if isinstance(value, str) and node.kind == "string":
            size = min(MAX_STRING, len(value.encode("utf-8", "surrogatepass")))
            self._string_bytes[node.address] = max(size, self._string_bytes.get(node.address, 0))
        return PointResult(value=value)

    async def _write(self, values: Mapping[Point, Value]) -> dict[Point, PointResult]:
        """Write the values, 32 nodes a request; a node's failure stays in its own result.

        A write of several nodes refused whole, the session working, in RUN, by a user who may
        write: the limit is learned from reads of the same nodes as a refused read learns it
        (READINGS.md row 7), and the nodes not written yet are sent again in smaller requests,
        once. A refusal with nothing to learn (the same nodes read in one request) fails.
        """
        items = [(node_for(point), point, value) for point, value in values.items()]
        results: dict[Point, PointResult] = {}
        learned = False
        while items:
            group = plan(items, self._wire, self._max_nodes)[0]
            try:
                result = await self._call("write", [self._wire(item) for item in group])
            except WriteRefused:
                if learned or len(group) == 1 or not await self._fewer_write_nodes(group):
                    raise
                learned = True
                continue
            items = items[len(group) :]
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

    def _wire(self, item: tuple[Node, Point, Value]) -> dict[str, Any]:
        """Return the write node of one item: its address and its encoded value."""
        return item[0].request(encode(item[0].kind, item[2], self._zone), write=True)

    async def _fewer_write_nodes(self, group: list[tuple[Node, Point, Value]]) -> bool:
        """After a write of these nodes was refused whole: True when reads show a lower limit.

        The same nodes are read in one request first; where that passes, the count was not
        why, and nothing is learned.
        """
        params = [node.request() for node, _point, _value in group]
        try:
            self._noted(await self._send("read", params))
        except RpcError:
            return await self._fewer_nodes(params) and self._max_nodes < len(group)
        return False

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
