"""Siemens S7-300/400/1200/1500 and S7-200 (CP 243-1) through S7comm on ISO-on-TCP (port 102)."""

from __future__ import annotations

from collections.abc import Awaitable, Callable, Mapping, Sequence
from dataclasses import dataclass
from datetime import datetime
import logging
from typing import ClassVar
from zoneinfo import ZoneInfo

import aiohttp

from ...client import PlcClient
from ...errors import (
    PlcAddressError,
    PlcProtocolError,
    PlcValueError,
    PlcWriteRefusedError,
)
from ...types import (
    ConnectionConfig,
    DeviceInfo,
    PlcStatus,
    Point,
    PointResult,
    ReadResult,
    TlsMode,
    Value,
    ValueKind,
)
from .address import DATA_TYPES, Variable, value_kind, variable
from .codec import check_value, decode, plc_time, span_of, write_items
from .link import S7Link, S7RequestError, endpoint, tsap_text, validate_options
from .planner import (
    DEFAULT_PDU,
    Span,
    WriteItem,
    assemble,
    extract,
    failed_needs,
    locate,
    plan_reads,
    plan_writes,
)
from .protocol import OK, SZL_IDENTITY, SZL_ORDER_CODE, SZL_STATE, cpu_mode, identity, item_error
from .session import Session

_LOGGER = logging.getLogger(__name__)

type Fetched = dict[Span, bytes | int]


@dataclass(frozen=True, slots=True)
class _Layout:
    """The points of a poll resolved: errors of invalid ones, variables, ranges to read."""

    points: tuple[Point, ...]
    errors: dict[Point, PointResult]
    groups: list[tuple[Variable, Span, list[Point]]]  # a variable, its range, its points
    needs: frozenset[Span]


class S7Client(PlcClient):
    """One S7 connection by rack/slot or TSAP; polls in PDU-packed multi-variable requests."""

    vendor: ClassVar[str] = "s7"
    default_port: ClassVar[int] = 102
    default_tls: ClassVar[TlsMode] = TlsMode.NONE
    tls_modes: ClassVar[tuple[TlsMode, ...]] = (TlsMode.NONE,)
    needs_credentials: ClassVar[bool] = False
    data_types: ClassVar[tuple[str, ...]] = DATA_TYPES
    default_scan_interval: ClassVar[float] = 2.0
    requested_pdu: ClassVar[int] = 960  # the PLC answers with what it can (240, 480, 960)
    reconnect_delay: ClassVar[tuple[float, float]] = (1.0, 60.0)  # first and longest wait

    def __init__(
        self, config: ConnectionConfig, session: aiohttp.ClientSession | None = None
    ) -> None:
        """Keep the settings (the options are checked here); nothing opens until used."""
        super().__init__(config, session)
        self._ends = endpoint(config.options)
        self._zone = ZoneInfo(config.time_zone)
        self._where = f"{config.host}:{config.port}"
        self._connection = Session(config, self._ends, self.metrics, lambda: self.reconnect_delay)
        self._seen = 0  # the session's link count when this client last looked
        self._alone: set[Span] = set()  # ranges that failed inside a merged item: read alone
        self._last_layout: _Layout | None = None
        self._last_plan: tuple[object, list[list[Span]], dict[Span, list[int]]] | None = None
        self._state_known = True  # False once the PLC refused SZL 0x0424 (S7-200, LOGO!)

    @classmethod
    def validate_options(cls, options: Mapping[str, object]) -> dict[str, str | int | bool]:
        """Return the vendor options normalized; raise PlcValueError (a ValueError)."""
        return validate_options(options)

    @classmethod
    def validate_point(cls, point: Point) -> Point:
        """Return the point with address and type normalized; raise PlcAddressError."""
        found = variable(point)
        return Point(found.text, found.data_type)

    @classmethod
    def validate_value(cls, point: Point, value: Value) -> Value:
        """Return the value checked for the point's type; raise PlcValueError."""
        return check_value(variable(point), value)

    @classmethod
    def value_kind(cls, point: Point) -> ValueKind | None:
        """What the point's values are (STRING[n] is text, DTL a date and time)."""
        return value_kind(point.data_type)

    @classmethod
    def requests_for(cls, points: Sequence[Point], pdu_size: int = DEFAULT_PDU) -> int:
        """Round trips of one poll: the packed reads, plus one for the CPU state.

        A class knows no PLC: it plans for the default PDU (480). Pass `client.pdu_size` for
        the size the PLC negotiated (240 on an S7-300, 960 on an S7-1500).
        """
        needs: set[Span] = set()
        for point in points:
            try:
                needs.add(span_of(variable(point)))
            except PlcAddressError:
                continue
        return len(plan_reads(needs, pdu_size)) + 1

    def planned_requests(self, points: Sequence[Point]) -> int:
        """Round trips of one poll at the PDU size this PLC negotiated."""
        return self.requests_for(points, self.pdu_size)

    @property
    def pdu_size(self) -> int:
        """The PDU size the PLC negotiated (the default before the first connection)."""
        return self._connection.pdu_size

    async def connect(self) -> DeviceInfo:
        """Open the S7 session and read the CPU's identity (SZL 0x0011 and 0x001C)."""

        async def read_identity(link: S7Link) -> dict[str, str]:
            order_code = await self._szl(link, SZL_ORDER_CODE)
            return identity(order_code, await self._szl(link, SZL_IDENTITY))

        found = await self._run(read_identity, fresh=True)
        extra: dict[str, str] = {
            key: found[key] for key in ("order_code", "module_name") if key in found
        }
        extra |= {"pdu_size": str(self.pdu_size), "remote_tsap": tsap_text(self._ends.remote_tsap)}
        return DeviceInfo(
            vendor=self.vendor,
            model=found.get("module_type") or found.get("order_code") or "SIMATIC S7",
            serial=found.get("serial"),
            firmware=found.get("firmware"),
            name=found.get("name"),
            extra=extra,
        )

    @staticmethod
    async def _szl(link: S7Link, szl_id: int) -> bytes | None:
        """Read a system status list; None when the PLC has none (S7-200, LOGO!)."""
        try:
            return await link.read_szl(szl_id)
        except S7RequestError as err:
            _LOGGER.debug("The PLC has no SZL 0x%04X: %s", szl_id, err)
            return None

    async def _read(self, points: Sequence[Point]) -> ReadResult:
        """Read every point in the fewest requests, then the CPU state (one more)."""
        layout = self._layout(points)

        async def poll(link: S7Link) -> tuple[Fetched, str | None]:
            return await self._fetch(link, layout.needs), await self._mode(link)

        got, mode = await self._run(poll)
        values = dict(layout.errors)
        for found, need, group in layout.groups:
            values.update(dict.fromkeys(group, self._outcome(found, got[need])))
        return ReadResult(values=values, status=PlcStatus(mode=mode))

    def _layout(self, points: Sequence[Point]) -> _Layout:
        """Resolve the points of a poll; a coordinator asks the same ones each time: kept."""
        if self._last_layout is None or self._last_layout.points != tuple(points):
            errors: dict[Point, PointResult] = {}
            wanted: dict[Variable, list[Point]] = {}
            for point in points:
                try:
                    wanted.setdefault(variable(point), []).append(point)
                except PlcAddressError as err:
                    errors[point] = PointResult(error=err)
            groups = [(found, span_of(found), group) for found, group in wanted.items()]
            needs = frozenset(need for _, need, _ in groups)
            self._last_layout = _Layout(tuple(points), errors, groups, needs)
        return self._last_layout

    async def _fetch(self, link: S7Link, needs: frozenset[Span]) -> Fetched:
        """Read the ranges; re-read alone (once) the ones that shared a failed item.

        The ones that fail alone stay alone in later polls; the others merge again.
        """
        plan, where = self._plan(needs, link.pdu_size)
        got = await self._read_plan(link, plan)
        fetched = {need: assemble(need, [got[p] for p in where[need]]) for need in needs}
        retry = failed_needs(needs, got) - self._alone
        if retry:
            again = await self._read_plan(link, plan_reads(retry, link.pdu_size, alone=retry))
            fetched |= extract(retry, again)
            self._alone |= {need for need in retry if isinstance(fetched[need], int)}
        return fetched

    def _plan(
        self, needs: frozenset[Span], pdu_size: int
    ) -> tuple[list[list[Span]], dict[Span, list[int]]]:
        """Plan the reads and where each need lies in them; kept while nothing changes."""
        key = (needs, pdu_size, frozenset(self._alone))
        if self._last_plan is None or self._last_plan[0] != key:
            plan = plan_reads(needs, pdu_size, alone=self._alone)
            where = locate(needs, [span for request in plan for span in request])
            self._last_plan = (key, plan, where)
        return self._last_plan[1], self._last_plan[2]

    @staticmethod
    async def _read_plan(link: S7Link, plan: list[list[Span]]) -> list[tuple[Span, bytes | int]]:
        """Send the planned read requests; pair each item with its data or return code."""
        got: list[tuple[Span, bytes | int]] = []
        for request in plan:
            try:
                items = await link.read(request)
            except S7RequestError as err:
                raise PlcProtocolError(
                    f"the PLC refused the read: {err} (an S7-1200/1500 must permit PUT/GET access)"
                ) from err
            for span, item in zip(request, items, strict=True):
                if isinstance(item, bytes) and len(item) != span.size:
                    raise PlcProtocolError(
                        f"the PLC answered {len(item)} bytes for an item of {span.size}"
                    )
                got.append((span, item))
        return got

    async def _mode(self, link: S7Link) -> str | None:
        """Return RUN or STOP (one SZL request); None where the PLC cannot tell."""
        if not self._state_known:
            return None
        try:
            return cpu_mode(await link.read_szl(SZL_STATE))
        except PlcProtocolError as err:
            _LOGGER.debug("%s reports no CPU state, not asking again: %s", self._where, err)
            self._state_known = False
            return None

    def _outcome(self, found: Variable, item: bytes | int) -> PointResult:
        """Return one point's value, or its own error."""
        if isinstance(item, int):
            return PointResult(error=item_error(item, found.text))
        try:
            return PointResult(value=decode(found, item, self._zone))
        except PlcProtocolError as err:
            return PointResult(error=err)

    async def _write(self, values: Mapping[Point, Value]) -> dict[Point, PointResult]:
        """Write every value in as few multi-variable requests as the PDU allows."""
        results: dict[Point, PointResult] = {}

        async def write(link: S7Link) -> dict[Point, list[int]]:
            flat: list[tuple[Point, WriteItem]] = []
            for point, value in values.items():
                try:
                    pieces = write_items(variable(point), value, self._zone, link.pdu_size)
                except PlcValueError as err:
                    results[point] = PointResult(error=err)
                    continue
                flat += [(point, piece) for piece in pieces]
            codes: dict[Point, list[int]] = {point: [] for point, _ in flat}
            done = 0
            for request in plan_writes([item for _, item in flat], link.pdu_size):
                try:
                    answers = await link.write(request)
                except S7RequestError as err:
                    raise PlcWriteRefusedError(f"the PLC refused the write: {err}") from err
                for code in answers:
                    codes[flat[done][0]].append(code)
                    done += 1
            return codes

        for point, codes in (await self._run(write)).items():
            bad = next((code for code in codes if code != OK), None)
            if bad is None:
                results[point] = PointResult(value=values[point])
            else:
                error = item_error(bad, variable(point).text, write=True)
                results[point] = PointResult(error=error)
        return results

    async def read_clock(self) -> datetime:
        """Return the PLC clock in the configured time zone."""
        return (await self._run(lambda link: link.get_clock())).replace(tzinfo=self._zone)

    async def set_clock(self, when: datetime) -> None:
        """Set the PLC clock (a naive time is taken as PLC local time)."""
        local = plc_time(when, self._zone, 1990, 2089, "the PLC clock")

        async def set_clock(link: S7Link) -> None:
            try:
                await link.set_clock(local)
            except S7RequestError as err:
                raise PlcWriteRefusedError(f"the PLC refused to set its clock: {err}") from err

        await self._run(set_clock)

    async def close(self) -> None:
        """Close the S7 session."""
        await self._connection.close()
        await self._close_own_session()

    async def _run[T](self, job: Callable[[S7Link], Awaitable[T]], *, fresh: bool = False) -> T:
        """Run a job on the session; forget what a previous link taught when it is new."""

        async def checked(link: S7Link) -> T:
            if self._seen != self._connection.opened:  # another link: maybe a new CPU or program
                self._seen = self._connection.opened
                self._alone.clear()
                self._state_known = True
            return await job(link)

        return await self._connection.run(checked, self.requested_pdu, fresh=fresh)
