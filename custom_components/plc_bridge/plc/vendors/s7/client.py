"""Siemens S7-300/400/1200/1500 and S7-200 (CP 243-1) through S7comm on ISO-on-TCP (port 102)."""

from __future__ import annotations

from collections.abc import Awaitable, Callable, Mapping, Sequence
from datetime import datetime
import logging
from typing import ClassVar
from zoneinfo import ZoneInfo

import aiohttp

from ...client import PlcClient
from ...errors import PlcAddressError, PlcWriteRefusedError
from ...shifting import BYTES, DATA_BLOCKS
from ...types import (
    ConnectionConfig,
    DeviceInfo,
    Footprint,
    Point,
    PointResult,
    ReadResult,
    TlsMode,
    Value,
    ValueKind,
)
from .address import (
    AREA_I,
    AREA_P,
    DATA_TYPES,
    Variable,
    on_s7_200,
    shift,
    value_kind,
    variable,
)
from .codec import check_value, plc_time, span_of
from .items import ItemLimit
from .link import S7Link, S7RequestError, endpoint, tsap_text, validate_options
from .planner import DEFAULT_PDU, Span, plan_reads
from .protocol import SZL_IDENTITY, SZL_ORDER_CODE, identity
from .reading import Reader, outcome
from .session import Session
from .status import StatusReader
from .writing import write_values

_LOGGER = logging.getLogger(__name__)


class S7Client(PlcClient):
    """One S7 connection by rack/slot or TSAP; polls in PDU-packed multi-variable requests."""

    vendor: ClassVar[str] = "s7"
    default_port: ClassVar[int] = 102
    default_tls: ClassVar[TlsMode] = TlsMode.NONE
    tls_modes: ClassVar[tuple[TlsMode, ...]] = (TlsMode.NONE,)
    needs_credentials: ClassVar[bool] = False
    uses_http: ClassVar[bool] = False
    shift_units: ClassVar[tuple[str, ...]] = (BYTES, DATA_BLOCKS)
    data_types: ClassVar[tuple[str, ...]] = DATA_TYPES
    default_scan_interval: ClassVar[float] = 2.0
    requested_pdu: ClassVar[int] = 960  # the PLC answers with what it can (240, 480, 960)
    reconnect_delay: ClassVar[tuple[float, float]] = (1.0, 60.0)  # first and longest wait
    status_interval: ClassVar[float] = 60.0  # state and clock cost a round trip each: once a minute
    # A request waits a poll interval, never less than this: an S7 CPU serves communication at
    # its cycle's end, and 1 s is several times the default maximum cycle time (150 ms)
    shortest_timeout: ClassVar[float] = 1.0

    def __init__(
        self, config: ConnectionConfig, session: aiohttp.ClientSession | None = None
    ) -> None:
        """Keep the settings (the options are checked here); nothing opens until used."""
        super().__init__(config, session)
        self._ends = endpoint(config.options)
        self._zone = ZoneInfo(config.time_zone)
        self._where = f"{config.host}:{config.port}"
        self._connection = Session(
            config, self._ends, self.metrics, lambda: self.reconnect_delay, self.shortest_timeout
        )
        self._seen = 0  # the session's link count when this client last looked
        self._items = ItemLimit()  # items a job: as many as the PDU holds, fewer once learned
        self._reader = Reader(self._variable, self._items)
        self._status = StatusReader(self._zone, self._where)

    def _variable(self, point: Point) -> Variable:
        """Resolve a point for this PLC (an S7-200 has timers and counters of its own)."""
        found = variable(point)
        return on_s7_200(found) if self._ends.s7_200 else found

    @classmethod
    def validate_options(cls, options: Mapping[str, object]) -> dict[str, str | int | bool]:
        """Return the vendor options normalized; raise PlcOptionError naming the field at fault."""
        return validate_options(options)

    @classmethod
    def validate_point(cls, point: Point) -> Point:
        """Return the point with address and type normalized; raise PlcAddressError."""
        found = variable(point)
        return Point(found.text, found.data_type)

    @classmethod
    def shift_point(cls, point: Point, by: int, unit: str, part: str = "") -> Point:
        """Return the point moved by bytes (DB10.DBW0 + 24 = DB10.DBW24) or by DB numbers."""
        return shift(point, by, unit)

    @classmethod
    def footprint(cls, point: Point) -> Footprint:
        """The area (a DB by its number) and bits a point covers; a timer or counter its number.

        Counted in bits: a BOOL goes out with the BIT transport size and writes that bit
        alone, so a bit beside a read-only bit of the same byte stays writable.
        """
        found = variable(point)
        area = f"{found.area}:{found.db}"
        if found.counted:
            return Footprint(area, found.start * 8, found.start * 8 + 8)
        if found.bit is not None:
            first = found.start * 8 + found.bit
            return Footprint(area, first, first + 1)
        return Footprint(area, found.start * 8, (found.start + found.size) * 8)

    @classmethod
    def address_writable(cls, point: Point) -> bool:
        """False for the inputs: I (E) and peripheral inputs PI (PE), whose writes reach outputs."""
        return variable(point).area not in (AREA_I, AREA_P)

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
        """Round trips of a typical poll: the packed reads.

        A class knows no PLC: it plans for the default PDU (480). Pass `client.pdu_size` for
        the size the PLC negotiated (240 on an S7-300, 960 on an S7-1500). Not counted: the
        CPU state and clock, two round trips more at the first poll of a connection and then
        once every `status_interval` (60 s).
        """
        needs: set[Span] = set()
        for point in points:
            try:
                needs.add(span_of(variable(point)))
            except PlcAddressError:
                continue
        return len(plan_reads(needs, pdu_size))

    def planned_requests(self, points: Sequence[Point]) -> int:
        """Round trips of one poll at the PDU size this PLC negotiated."""
        return self.requests_for(points, self.pdu_size)

    @property
    def request_timeout(self) -> float:
        """Seconds a request waits for its answer (about one poll interval; session.py)."""
        return self._connection.timeout

    @property
    def pdu_size(self) -> int:
        """The PDU size the PLC negotiated (the default before the first connection)."""
        return self._connection.pdu_size

    async def connect(self) -> DeviceInfo:
        """Open the S7 session; read the identity (SZL 0x0011 and 0x001C)."""

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

    async def _read(self, points: Sequence[Point], *, poll: bool) -> ReadResult:
        """Read every point in the fewest requests; in a poll, the status when it is due."""
        layout = self._reader.layout(points, keep=poll)

        async def read(link: S7Link) -> ReadResult:
            got = await self._reader.fetch(link, layout.needs)
            values = dict(layout.errors)
            for found, need, group in layout.groups:
                values.update(dict.fromkeys(group, outcome(found, got[need], self._zone)))
            if not poll:
                return ReadResult(values=values)
            status = await self._status.read(link, self.status_interval)
            return ReadResult(values=values, status=status)

        return await self._run(read)

    async def _write(self, values: Mapping[Point, Value]) -> dict[Point, PointResult]:
        """Write every value in as few multi-variable requests as the PDU allows."""
        checked = {point: (self._variable(point), value) for point, value in values.items()}
        return await self._run(lambda link: write_values(link, checked, self._zone, self._items))

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
            self._status.clock_due()

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
                self._reader.forget()
                self._status.forget()
                self._items.forget()
            return await job(link)

        return await self._connection.run(checked, self.requested_pdu, fresh=fresh)
