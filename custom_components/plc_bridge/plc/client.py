"""The vendor-neutral client interface every vendor module implements."""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping, Sequence
from contextvars import ContextVar
from datetime import datetime
import math
import time
from typing import ClassVar

import aiohttp

from .codec import IEC_KINDS
from .errors import PlcAddressError, PlcError
from .http import client_session
from .types import (
    BrowseItem,
    ClientMetrics,
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

ResultsCallback = Callable[[dict[Point, PointResult]], None]
"""Takes the results of one request of a read, as soon as that request has returned."""
_ON_RESULTS: ContextVar[ResultsCallback | None] = ContextVar("plc_bridge_results", default=None)


class PlcClient(ABC):
    """One connection to one PLC.

    A vendor subclass sets the class attributes and implements `validate_point`, `connect`,
    `_read`, `_write`, `read_clock`, `set_clock` and `close`; `browse` where the PLC can list its
    variables. Every request goes through one choke point in the vendor (usually
    `HttpTransport.request`) that counts it in `metrics`.
    """

    vendor: ClassVar[str]
    default_port: ClassVar[int]
    default_tls: ClassVar[TlsMode] = TlsMode.NONE
    tls_modes: ClassVar[tuple[TlsMode, ...]] = (TlsMode.NONE,)
    needs_credentials: ClassVar[bool] = False
    credentials_optional: ClassVar[bool] = False  # asked, but may stay empty (auth may be off)
    credential_option: ClassVar[str | None] = None  # the option that authenticates, if not a user
    data_types: ClassVar[tuple[str, ...]]
    typed_data_types: ClassVar[bool] = (
        True  # False: a form offers `data_types` only (STRING[20]: a table)
    )
    default_scan_interval: ClassVar[float] = 5.0
    max_points_per_request: ClassVar[int] = 0  # 0: the vendor packs by size, not count
    request_interval: ClassVar[float] = 0.0  # pacing between requests, in seconds
    can_browse: ClassVar[bool] = False
    uses_http: ClassVar[bool] = True  # False: the vendor never touches `session`
    shift_units: ClassVar[tuple[str, ...]] = ()
    """What a template's stride may count (plc/shifting.py), the usual first; none: no templates."""

    def __init__(
        self, config: ConnectionConfig, session: aiohttp.ClientSession | None = None
    ) -> None:
        """Keep the settings and the injected session; nothing is opened until `connect`."""
        self.config = config
        self.metrics = ClientMetrics()
        self._session = session
        self._own_session = session is None
        self.unlisted: list[str] = []  # what the last browse could not list

    @property
    def session(self) -> aiohttp.ClientSession:
        """The injected aiohttp session, or one of the client's own made on first use.

        The client's own keeps an idle connection for the poll interval (`client_session`).
        """
        if self._session is None:
            self._session = client_session(self.config)
        return self._session

    def own_session(self) -> None:
        """Take the injected session as the client's own: `close` closes it too."""
        self._own_session = True

    async def _close_own_session(self) -> None:
        """Close the session the client made itself (never an injected one)."""
        if self._own_session and self._session is not None:
            await self._session.close()
            self._session = None

    @classmethod
    @abstractmethod
    def validate_point(cls, point: Point) -> Point:
        """Return the point with its address normalized; raise PlcAddressError when invalid."""

    @classmethod
    def validate_options(cls, options: Mapping[str, object]) -> dict[str, str | int | bool]:
        """Return the vendor options normalized; raise PlcValueError with a form-ready message."""
        return {k: v for k, v in options.items() if isinstance(v, str | int | bool)}

    @classmethod
    def configured(cls, options: Mapping[str, object]) -> type[PlcClient]:
        """Return the class whose address checks know a PLC's options (itself, unless they matter).

        The forms check addresses before any client exists; a vendor whose valid addresses
        depend on its options (a LOGO!'s generation) answers with a class bound to them.
        Options that are not valid give the class itself: their own check reports them.
        """
        return cls

    @classmethod
    def resolve_options(
        cls, folder: str, submitted: Mapping[str, object], stored: Mapping[str, object]
    ) -> dict[str, str]:
        """Return the submitted options that name files, resolved in `folder` (blocking I/O).

        A vendor whose options may be files (SoftPLC's client certificate and key) checks them
        here; raise PlcOptionError on the option at fault. Others have none.
        """
        return {}

    @classmethod
    def validate_value(cls, point: Point, value: Value) -> Value:
        """Return the value coerced for the point; raise PlcValueError before anything is sent."""
        return value

    @classmethod
    def value_kind(cls, point: Point) -> ValueKind | None:
        """What a valid point's values are (None: unknown); by IEC type name unless overridden."""
        return IEC_KINDS.get(point.data_type.strip().upper())

    @classmethod
    def requests_for(cls, points: Sequence[Point]) -> int:
        """How many requests one poll of these points takes (the planner's count)."""
        if not points:
            return 0
        if cls.max_points_per_request:
            return math.ceil(len(points) / cls.max_points_per_request)
        return 1

    def planned_requests(self, points: Sequence[Point]) -> int:
        """How many requests one poll of these points takes on this PLC, as connected.

        The class-level `requests_for` plans without a PLC; a vendor whose plan depends on what
        the PLC negotiated (the S7 PDU size) overrides this.
        """
        return self.requests_for(points)

    @classmethod
    def footprint(cls, point: Point) -> Footprint:
        """What a valid point covers in the PLC, to tell whether two points touch the same data.

        The default is the name as typed, for vendors whose points are names compared exactly.
        A vendor with memory areas returns the area and the byte range a point covers (so that
        `VW100` and `VB101` overlap); one whose names are case-insensitive folds the case.
        """
        return Footprint(point.address, 0, 1)

    def covers(self, point: Point) -> Footprint:
        """What a valid point covers as this client has seen the PLC (the write guard's view).

        `footprint` unless the vendor learns more from its reads (an S7-200 SMART string's
        length, which only its length byte in the PLC tells).
        """
        return self.footprint(point)

    @classmethod
    def write_footprint(cls, point: Point) -> Footprint:
        """What a write of a valid point changes in the PLC: its footprint, or more.

        A vendor that writes more than the point overrides it (SoftPLC writes a bit's word).
        """
        return cls.footprint(point)

    @classmethod
    def shift_point(cls, point: Point, by: int, unit: str, part: str = "") -> Point:
        """Return a valid point moved by `by` units of `unit`, for a copy of its machine.

        `part` is the part of a variable name that counts, for a vendor of names. Raise
        PlcAddressError where the point cannot move so: out of its area, the part not in its
        name, a unit the vendor has not.
        """
        raise PlcAddressError(f"{point.address}: this PLC's addresses are not moved by {unit}")

    @classmethod
    def address_writable(cls, point: Point) -> bool:
        """False where no write can ever reach the address: an input, a read-only area.

        Decided from the address alone (the PLC may refuse more); the default allows all.
        """
        return True

    @classmethod
    def min_scan_interval(cls, points: Sequence[Point]) -> float:
        """The shortest poll interval that respects the vendor's advised request rate.

        Also how long one poll of these points takes at that rate: the real poll cycle where
        the interval asked for is shorter.
        """
        return cls.request_interval * max(1, cls.requests_for(points))

    @classmethod
    def points_read_within(cls, points: Sequence[Point], seconds: float) -> int:
        """How many of the points, from the first, one read takes in at most `seconds` of pacing.

        All of them where the vendor paces no requests; at least one.
        """
        if cls.min_scan_interval(points) <= seconds:
            return len(points)
        low, high = 1, len(points)
        while low < high:
            middle = (low + high + 1) // 2
            if cls.min_scan_interval(points[:middle]) <= seconds:
                low = middle
            else:
                high = middle - 1
        return low

    @abstractmethod
    async def connect(self) -> DeviceInfo:
        """Open the connection, log in and return what the PLC says about itself."""

    async def check_access(self) -> None:
        """After `connect`, check what only writes use (SoftPLC's client certificate).

        Called where settings are entered, so that a refusal shows there; never by a setup,
        whose reads must go on whatever writes would meet.
        """
        return  # most vendors check everything in `connect`

    async def read(
        self,
        points: Sequence[Point],
        *,
        poll: bool = True,
        on_results: ResultsCallback | None = None,
    ) -> ReadResult:
        """Read every point in the fewest requests the vendor allows.

        A poll (the coordinator's) is counted in the metrics and may keep state for the next
        poll (plans, unknown names, the status); an on-demand read (`poll=False`, the read
        action) touches none of that and reads no status. `on_results` is handed each
        request's results as it returns, by a vendor that reads in several paced requests
        (the others may hand nothing); the returned result holds every point all the same.
        """
        before = self.metrics.requests
        started = time.perf_counter()
        token = _ON_RESULTS.set(on_results)
        try:
            return await self._read(points, poll=poll)
        except PlcError:
            self.metrics.errors += 1
            raise
        finally:
            _ON_RESULTS.reset(token)
            if poll:
                self.metrics.polls += 1
                self.metrics.last_poll_requests = self.metrics.requests - before
                self.metrics.last_poll_ms = (time.perf_counter() - started) * 1000

    async def write(self, values: Mapping[Point, Value]) -> dict[Point, PointResult]:
        """Write every value in as few requests as the vendor allows; a result per point."""
        checked = {point: self.validate_value(point, value) for point, value in values.items()}
        try:
            return await self._write(checked)
        except PlcError:
            self.metrics.errors += 1
            raise

    @abstractmethod
    async def _read(self, points: Sequence[Point], *, poll: bool) -> ReadResult:
        """Vendor part of `read`; keep poll state only when `poll` is true."""

    @staticmethod
    def _request_results(values: dict[Point, PointResult]) -> None:
        """Hand one request's results to the `on_results` of the read running (if it has one).

        Kept out of `_read`'s arguments: a vendor reading in one request has nothing to hand.
        """
        on_results = _ON_RESULTS.get()
        if on_results is not None and values:
            on_results(values)

    @abstractmethod
    async def _write(self, values: Mapping[Point, Value]) -> dict[Point, PointResult]:
        """Vendor part of `write`; values are already validated."""

    async def browse(self) -> list[BrowseItem]:
        """List the variables the PLC publishes (empty where the vendor cannot).

        A vendor that cannot list some of them sets `unlisted` to their addresses.
        """
        return []

    @property
    def can_set_clock(self) -> bool:
        """True when `set_clock` can work with the settings given (vendors override)."""
        return True

    @abstractmethod
    async def read_clock(self) -> datetime:
        """Return the PLC's clock as a timezone-aware datetime."""

    @abstractmethod
    async def set_clock(self, when: datetime) -> None:
        """Set the PLC's clock."""

    @abstractmethod
    async def close(self) -> None:
        """Log out where the vendor has sessions and release the connection."""
