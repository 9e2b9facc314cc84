"""The Tecomat TecoApi client: GetInfo, GetList, GetObject and PutObject over HTTP(S)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from datetime import datetime
import logging
from time import monotonic
from typing import Any, ClassVar
from zoneinfo import ZoneInfo

import aiohttp

from ...client import PlcClient
from ...codec import clock_option
from ...errors import (
    PlcAddressError,
    PlcConnectionError,
    PlcError,
    PlcProtocolError,
    PlcValueError,
    PlcWriteRefusedError,
)
from ...planning import chunks, distinct
from ...shifting import NAME
from ...types import (
    BrowseItem,
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
from .api import AUTH_METHODS, TecoApi
from .arrays import (
    array_plan,
    elements_later,
    from_zero,
    known,
    list_corners,
    place_again,
    place_arrays,
    place_whole,
)
from .browse import LIST_URI, Listing, expand, listed_names
from .codec import KINDS, TYPES, check_value, data_type, decode, encode, same_value
from .info import device_info, plc_status
from .paths import (
    MAX_VARIABLES,
    SERVICE,
    VariablePath,
    check_writable,
    parse_path,
    plan,
    shift,
)
from .reading import Plan, Reading, results, under
from .unknown import UnknownVariables

_LOGGER = logging.getLogger(__name__)
_NOT_READ_BACK = PlcProtocolError("written, not read back")  # a marker: the write stands


@dataclass(frozen=True, slots=True)
class _Write:
    """One point of a PutObject: where, as which type, what."""

    point: Point
    path: VariablePath
    kind: str
    value: Value


class TecomatClient(PlcClient):
    """A Tecomat Foxtrot or TC700 PLC through its web server's TecoApi."""

    vendor: ClassVar[str] = "tecomat"
    shift_units: ClassVar[tuple[str, ...]] = (NAME,)
    default_port: ClassVar[int] = 80
    default_tls: ClassVar[TlsMode] = TlsMode.NONE
    tls_modes: ClassVar[tuple[TlsMode, ...]] = (
        TlsMode.NONE,
        TlsMode.PIN,
        TlsMode.VERIFY,
        TlsMode.OFF,
    )
    needs_credentials: ClassVar[bool] = True
    data_types: ClassVar[tuple[str, ...]] = TYPES
    can_browse: ClassVar[bool] = True
    status_interval: ClassVar[float] = 60.0  # GetInfo costs a request of its own: not every poll

    def __init__(
        self, config: ConnectionConfig, session: aiohttp.ClientSession | None = None
    ) -> None:
        """Keep the settings; the transport and the digest state are made on first use."""
        super().__init__(config, session)
        self._api: TecoApi | None = None
        self._zone = ZoneInfo(config.time_zone)
        self._status = PlcStatus()
        self._status_at = -float("inf")
        self._plan: tuple[tuple[tuple[str, ...], int | None], list[list[VariablePath]]] | None = (
            None
        )
        self._unknown = UnknownVariables()
        # Arrays by key: asked element by element (too big, 413.004, or not from 0); the first
        # index of every dimension, confirmed or declared (JSON arrays indexed by position);
        # lists answered to elements whose probe did not confirm them (not probed again).
        self._by_elements: set[str] = set()
        self._lows: dict[str, tuple[int, ...]] = {}
        self._unconfirmed: set[str] = set()
        self._declared = False  # GetList's declared bounds are in _lows (once a program)
        self._stamp: str | None = None  # the program's stamp (GetInfo, 3.2)
        self._parsed: dict[Point, tuple[VariablePath, str] | PlcError] = {}  # the last poll's
        self._poll: Plan | None = None
        self._status_read = False  # GetInfo was asked in this poll
        self._unread_logged: set[str] = set()  # variables whose read-back failed, warned once

    @classmethod
    def validate_options(cls, options: Mapping[str, object]) -> dict[str, str | int | bool]:
        """Return the authentication and the clock variable's path; raise PlcValueError."""
        auth = str(options.get("auth") or "digest").strip().lower()
        if auth not in AUTH_METHODS:
            raise PlcValueError(f"the authentication is Digest or Basic, not {auth!r}")
        settings: dict[str, str | int | bool] = {"auth": auth}
        return settings | clock_option(options, lambda text: parse_path(text).text)

    @classmethod
    def validate_point(cls, point: Point) -> Point:
        """Return the point with its path and type normalized; raise PlcAddressError."""
        return Point(parse_path(point.address).text, data_type(point.data_type))

    @classmethod
    def shift_point(cls, point: Point, by: int, unit: str, part: str = "") -> Point:
        """Return the point whose counting part moved (`Shutter_1.` + 1: `Shutter_2.`)."""
        if unit != NAME:
            raise PlcAddressError(f"{point.address}: a TecoApi name moves by the number in it")
        return cls.validate_point(Point(shift(point.address, part, by), point.data_type))

    @classmethod
    def footprint(cls, point: Point) -> Footprint:
        """The variable's path case-folded (the PLC's names are): `a` covers `A.b` and `a[2]`."""
        return Footprint.of_path(
            str(part).casefold() for part in parse_path(point.address).segments
        )

    @classmethod
    def validate_value(cls, point: Point, value: Value) -> Value:
        """Return the value checked for the point's type and the PutObject parser (3.6)."""
        path = parse_path(point.address)
        check_writable(path)
        return check_value(data_type(point.data_type), value, path.text)

    @classmethod
    def value_kind(cls, point: Point) -> ValueKind | None:
        """Return what the point holds; TIME and TOD are durations (sent as hh:mm:ss.zzz)."""
        try:
            return KINDS[data_type(point.data_type)]
        except PlcAddressError:
            return None

    @classmethod
    def requests_for(cls, points: Sequence[Point]) -> int:
        """Count the GetObject requests of one poll (URI <= 256 characters, 128 names)."""
        paths = distinct(points, parse_path, data_type)
        return len(plan(array_plan(paths, set()).asked.values()))

    def _teco(self) -> TecoApi:
        """Return the service layer, made on first use."""
        if self._api is None:
            self._api = TecoApi(self.config, self.session, self.metrics, self.request_interval)
        return self._api

    async def connect(self) -> DeviceInfo:
        """Ask GetInfo: device information, PLC mode, program and clock (checks credentials)."""
        info = await self._teco().ask("GET", SERVICE + "GetInfo")
        device = device_info(info)
        self._take_status(info)
        return device

    def _take_status(self, info: Any) -> None:
        """Keep a GetInfo answer's status; a new program stamp asks every name and array again."""
        self._status, self._status_at = plc_status(info, self._zone), monotonic()
        stamp = self._status.extra.get("program_stamp")
        if stamp != self._stamp:
            self._unknown.clear()
            self._by_elements.clear()
            self._lows.clear()
            self._unconfirmed.clear()
            self._declared = False
            self._stamp = stamp

    async def _poll_status(self) -> PlcStatus:
        """Return the PLC status; GetInfo is asked again once `status_interval` has passed."""
        if monotonic() - self._status_at >= self.status_interval:
            await self._new_program()
        return self._status

    async def _new_program(self) -> bool:
        """Ask GetInfo (once a poll at most); True when the program's stamp changed."""
        if self._status_read:
            return False
        before = self._stamp
        self._take_status(await self._teco().ask("GET", SERVICE + "GetInfo"))
        self._status_read = True
        return self._stamp != before

    def _parse(
        self, points: Sequence[Point], poll: bool
    ) -> dict[Point, tuple[VariablePath, str] | PlcError]:
        """Return each point's path and type, or its error; kept for the next poll's points."""
        last, parsed = self._parsed, {}
        for point in points:
            found = last.get(point)
            if found is None:
                try:
                    found = parse_path(point.address), data_type(point.data_type)
                except PlcError as err:
                    found = err
            parsed[point] = found
        if poll:
            self._parsed = parsed
        return parsed

    def _prepare(self, points: Sequence[Point], poll: bool) -> Plan:
        """Return the points parsed, their distinct paths; a poll's kept while its points stay."""
        listed = tuple(points)
        if poll and self._poll is not None and self._poll.points == listed:
            return self._poll
        plan = Plan(listed)
        for point, found in self._parse(listed, poll).items():
            if isinstance(found, PlcError):
                plan.errors[point] = PointResult(error=found)
            else:
                plan.want(point, *found)
        if poll:
            self._poll = plan
        return plan

    async def _read(self, points: Sequence[Point], *, poll: bool) -> ReadResult:
        """Read every distinct path once, packed into the fewest GetObject requests.

        A value the PLC sent exactly as at the last poll keeps its last result (`LastResults`).
        """
        self._status_read = False
        try:
            if poll:
                await self._poll_status()
            plan = self._prepare(points, poll)
            reading = await self._read_paths(plan.paths, poll)
        finally:
            self._status_read = False  # outside a poll (read_clock), GetInfo is always asked
        values = results(reading, plan, self._zone)
        return ReadResult(values=values, status=self._status if poll else PlcStatus())

    async def _read_paths(self, paths: dict[str, VariablePath], poll: bool) -> Reading:
        """Read paths; an array holding several of them is read whole and indexed here (5.2).

        A JSON array is indexed by position from the first indices GetList declares, else once
        the PLC confirmed it starts at 0 (its first and last elements, one request, once a
        program); else, and for an array too big for one answer (413.004), its elements are
        asked by their own index, from then on.
        """
        arrays = array_plan(paths, self._by_elements)
        reading = await self._get_paths(arrays.asked, poll)
        placed = place_arrays(arrays, reading, self._by_elements, self._lows)
        if placed.unconfirmed:
            await self._declare()
        for key in [key for key in placed.unconfirmed if key in self._lows]:
            del placed.unconfirmed[key]
            place_whole(arrays, key, reading, self._lows)
        if placed.unconfirmed:
            ends = [path for pair in placed.unconfirmed.values() for path in pair]
            proof = await self._teco().get(plan(ends))
            for key, pair in placed.unconfirmed.items():
                if known(proof, pair):
                    depth = len(pair[0].segments) - len(arrays.asked[key].segments)
                    self._lows[key] = tuple(0 for _ in range(depth))
                    place_whole(arrays, key, reading, self._lows)
                else:
                    elements_later(key, arrays.inside[key], self._by_elements, placed)
        if placed.later:
            reading.merge(await self._get_paths(placed.later, poll))
        return reading

    async def _declare(self) -> None:
        """Take the arrays' first indices GetList declares (READINGS.md row 18), once a program.

        A GetList that lists names only declares none; one the PLC refuses declares none either.
        """
        if self._declared:
            return
        declared: dict[str, tuple[int, ...]] = {}
        try:
            listed_names(await self._teco().ask("GET", LIST_URI), declared)
        except PlcConnectionError:
            raise
        except PlcError as err:
            _LOGGER.debug("GetList gave no array bounds: %s", err)
        self._declared = True
        for key, lows in declared.items():
            self._lows.setdefault(key, lows)

    async def _place_lists(self, reading: Reading) -> None:
        """Place the lists answered to elements of arrays whose first index was not known.

        GetList's declared bounds first; then one request probes the corners of the rest, once
        a program (arrays.from_zero); one not confirmed keeps its points failed.
        """
        unplaced = [
            path
            for _answer, asked in reading.answers
            for path in asked
            if path.key not in reading.found
        ]
        todo = {
            key: (array, lengths)
            for key, (array, lengths) in reading.lists.items()
            if key not in self._lows
            and key not in self._unconfirmed
            and any(under(path, array) for path in unplaced)
        }
        if todo:
            await self._declare()
            todo = {key: found for key, found in todo.items() if key not in self._lows}
        if todo:
            corners = [list_corners(array, lengths) for array, lengths in todo.values()]
            proof = await self._teco().get(plan(path for pair in corners for path in pair))
            for key, (array, lengths) in todo.items():
                if from_zero(proof, array, lengths):
                    self._lows[key] = tuple(0 for _ in lengths)
                else:
                    self._unconfirmed.add(key)
        if any(key in self._lows for key in reading.lists):
            place_again(reading, self._lows)

    async def _get_paths(self, paths: dict[str, VariablePath], poll: bool) -> Reading:
        """Read paths; a poll skips the variables found unknown, each asked again on its timer."""
        if not poll:
            reading = await self._teco().get(plan(paths.values()), self._lows)
            await self._place_lists(reading)
            return reading
        unknown, now = self._unknown, monotonic()
        skipped: dict[str, PlcError] = {}
        if unknown:
            unknown.keep_used(paths.values())
            due = unknown.due(now)
            if due and await self._new_program():
                due = []  # a new program: every name rides with this poll's request
            for gone in due:
                if await self._teco().exists(gone.path):
                    unknown.found(gone.path.key)
                else:
                    unknown.still_gone(gone.path.key, now)
            paths, skipped = unknown.skip(paths)
        reading = await self._teco().get(self._planned(paths), self._lows)
        if any(key not in unknown for key in reading.gone):
            await self._new_program()  # the stamp as the variable went: a change then shows
        unknown.add(reading.gone.values(), now)
        await self._place_lists(reading)
        reading.failed.update(skipped)
        return reading

    def _planned(self, paths: dict[str, VariablePath]) -> list[list[VariablePath]]:
        """Return the request groups of a poll; the last poll's plan is kept (polls repeat)."""
        names = tuple(paths)
        limit = self._teco().max_names
        if self._plan is None or self._plan[0] != (names, limit):
            groups = plan(paths.values())
            if limit:  # the PLC refused as many names a request (413.002): kept from then on
                groups = [list(part) for group in groups for part in chunks(group, limit)]
            self._plan = (names, limit), groups
        return self._plan[1]

    async def _write(self, values: Mapping[Point, Value]) -> dict[Point, PointResult]:
        """Write every value with one PutObject (128 variables a request at most)."""
        items = [
            _Write(point, parse_path(point.address), data_type(point.data_type), value)
            for point, value in values.items()
        ]
        results: dict[Point, PointResult] = {}
        for group in chunks(items, MAX_VARIABLES):
            pairs = [(item.path, encode(item.kind, item.value, self._zone)) for item in group]
            failures = await self._teco().put(pairs)
            taken = [item for index, item in enumerate(group) if index not in failures]
            failures |= await self._not_taken(group, taken)
            for index, item in enumerate(group):
                error = failures.get(index)
                if error is _NOT_READ_BACK:
                    results[item.point] = PointResult()  # done; the next poll shows its value
                    continue
                if error is None:
                    self._unknown.found(item.path.key)
                results[item.point] = PointResult(value=None if error else item.value, error=error)
        return results

    async def _not_taken(self, group: Sequence[_Write], taken: list[_Write]) -> dict[int, PlcError]:
        """Read the written variables back; return the ones the PLC does not hold.

        A PutObject's 204 carries nothing that proves the values were taken (3.6), and some
        firmware answers so to values it dropped. A read-back that gets no usable answer proves
        nothing either way: the write the PLC acknowledged stands, its value unshown (`unread`).
        """
        if not taken:
            return {}
        paths = {item.path.key: item.path for item in taken}
        try:
            reading = await self._teco().get(plan(paths.values()), self._lows)
            await self._place_lists(reading)
        except PlcError as err:
            reading = Reading(failed=dict.fromkeys(paths, err))
        failures: dict[int, PlcError] = {}
        for index, item in enumerate(group):
            if item not in taken:
                continue
            try:
                held = decode(item.kind, reading.found[item.path.key], self._zone, item.path.text)
            except (KeyError, PlcError) as err:
                self._unread(item, reading.failed.get(item.path.key, err))
                failures[index] = _NOT_READ_BACK
                continue
            if not same_value(item.kind, held, item.value, self._zone):
                failures[index] = PlcWriteRefusedError(
                    f"{item.path.text}: the PLC answered the write but holds {held!r}, "
                    f"not {item.value!r}"
                )
        return failures

    def _unread(self, item: _Write, error: BaseException) -> None:
        """Log a write the PLC acknowledged whose read-back failed: once a variable, a warning."""
        key = item.path.key
        level = logging.DEBUG if key in self._unread_logged else logging.WARNING
        self._unread_logged.add(key)
        _LOGGER.log(level, "%s: written, not read back (%s)", item.path.text, error)

    async def browse(self) -> list[BrowseItem]:
        """List the public variables (GetList) and expand each value into its leaves."""
        paths: dict[str, VariablePath] = {}
        listing = Listing()
        for name in listed_names(await self._teco().ask("GET", LIST_URI), listing.declared):
            try:
                path = parse_path(name)
            except PlcAddressError:
                continue
            paths.setdefault(path.key, path)
        await expand(self._teco(), list(paths.values()), listing)
        self.unlisted = listing.unlisted
        self._lows |= listing.lows
        for key, lows in listing.declared.items():  # this program's GetList: no need to ask
            self._lows.setdefault(key, lows)
        self._declared = True
        return listing.items

    @property
    def can_set_clock(self) -> bool:
        """True once a clock variable is chosen: TecoApi has no service that sets the clock."""
        return bool(str(self.config.options.get("clock_variable", "")).strip())

    async def read_clock(self) -> datetime:
        """Return the PLC time GetInfo reports (3.2), in the configured time zone."""
        self._status_at = -float("inf")
        status = await self._poll_status()
        if status.clock is None:
            raise PlcProtocolError("the PLC's GetInfo answer holds no valid time")
        return status.clock

    async def set_clock(self, when: datetime) -> None:
        """Write the time to the clock variable (a DT the PLC program copies into its clock)."""
        variable = str(self.config.options.get("clock_variable", "")).strip()
        if not variable:
            raise PlcWriteRefusedError(
                "TecoApi has no service that sets the PLC clock: choose a DT variable that the "
                "PLC program copies into its clock as the PLC's clock variable"
            )
        point = Point(variable, "DT")
        error = (await self.write({point: when}))[point].error
        if error is not None:
            raise error
        self._status_at = -float("inf")  # the next poll asks GetInfo: the clock shows it

    async def close(self) -> None:
        """Release the client's own session (TecoApi has no logout)."""
        self._api = None
        await self._close_own_session()
