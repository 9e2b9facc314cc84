"""The PLCnext client: REST data interface, one group read per poll, one PUT per write."""

from __future__ import annotations

import asyncio
from collections.abc import Mapping, Sequence
from datetime import datetime
import logging
from typing import Any, ClassVar
from zoneinfo import ZoneInfo

import aiohttp

from ...client import PlcClient
from ...codec import clock_option
from ...errors import (
    PlcAddressError,
    PlcAuthenticationError,
    PlcError,
    PlcProtocolError,
    PlcWriteRefusedError,
)
from ...planning import distinct
from ...shifting import NAME
from ...types import (
    BrowseItem,
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
from .api import PlcnextApi
from .browse import (
    DATA_DICTIONARY,
    TYPE_DICTIONARY,
    declared,
    elementary,
    leaves,
    members,
    types,
)
from .codec import KINDS, TYPES, check_value, data_type, encode
from .errors import ApiError, request_error
from .info import device_info, plc_status
from .paths import VariablePath, parse_path, shift
from .placing import Reading
from .reading import Reader
from .results import Plan, outcome, results
from .writing import put

_LOGGER = logging.getLogger(__name__)
CLOSE_TIMEOUT = 2.0


class PlcnextClient(PlcClient):
    """A Phoenix Contact PLCnext Control through its REST data interface."""

    vendor: ClassVar[str] = "plcnext"
    shift_units: ClassVar[tuple[str, ...]] = (NAME,)
    default_port: ClassVar[int] = 443
    default_tls: ClassVar[TlsMode] = TlsMode.PIN
    tls_modes: ClassVar[tuple[TlsMode, ...]] = (TlsMode.PIN, TlsMode.VERIFY, TlsMode.OFF)
    needs_credentials: ClassVar[bool] = True
    credentials_optional: ClassVar[bool] = True  # a PLC with user authentication off
    data_types: ClassVar[tuple[str, ...]] = TYPES
    can_browse: ClassVar[bool] = True

    def __init__(
        self, config: ConnectionConfig, session: aiohttp.ClientSession | None = None
    ) -> None:
        """Keep the settings; the version, token, session and group come with use."""
        super().__init__(config, session)
        self._api: PlcnextApi | None = None
        self._reader: Reader | None = None
        self._zone = ZoneInfo(config.time_zone)
        self._last: Plan | None = None  # the last poll's points, parsed

    @classmethod
    def validate_options(cls, options: Mapping[str, object]) -> dict[str, str | int | bool]:
        """Return the clock variable's path, normalized; raise PlcValueError."""
        return clock_option(options, lambda text: parse_path(text).text)

    @classmethod
    def validate_point(cls, point: Point) -> Point:
        """Return the point with its full path and type name; raise PlcAddressError."""
        return Point(parse_path(point.address).text, data_type(point.data_type))

    @classmethod
    def shift_point(cls, point: Point, by: int, unit: str, part: str = "") -> Point:
        """Return the point whose counting part moved (`Shutter[1].` + 1: `Shutter[2].`)."""
        if unit != NAME:
            raise PlcAddressError(f"{point.address}: a PLCnext name moves by the number in it")
        return cls.validate_point(Point(shift(point.address, part, by), point.data_type))

    @classmethod
    def footprint(cls, point: Point) -> Footprint:
        """The variable's full path case-folded (IEC names are): `a` covers `A.b` and `a[2]`."""
        path = parse_path(point.address)
        return Footprint.of_path(str(part).casefold() for part in (path.component, *path.segments))

    @classmethod
    def validate_value(cls, point: Point, value: Value) -> Value:
        """Return the value checked for the point's IEC type; raise PlcValueError."""
        path = parse_path(point.address)
        return check_value(data_type(point.data_type), value, path.text)

    @classmethod
    def value_kind(cls, point: Point) -> ValueKind | None:
        """Return what the point holds (TIME and LTIME: durations, sent as ms and ns counts)."""
        try:
            return KINDS[data_type(point.data_type)]
        except PlcAddressError:
            return None

    @classmethod
    def requests_for(cls, points: Sequence[Point]) -> int:
        """One poll is one group read, whatever the number of points."""
        return 1 if distinct(points, parse_path, data_type) else 0

    def _rest(self) -> PlcnextApi:
        """Return the service layer, made on first use."""
        if self._api is None:
            self._api = PlcnextApi(self.config, self.session, self.metrics)
            self._reader = Reader(self._api, self.config.poll_interval)
        return self._api

    def _poller(self) -> Reader:
        """Return the poll state."""
        self._rest()
        assert self._reader is not None
        return self._reader

    async def connect(self) -> DeviceInfo:
        """Read the service description, log in where the PLC asks, open a session."""
        api = self._rest()
        description = await api.describe()
        if api.can_login and api.auth_required is not False:
            await api.login()
        await api.open_session()
        if api.auth_required and not api.can_login:
            raise PlcAuthenticationError(
                "the PLC has user authentication on: enter a PLCnext user and password"
            )
        return device_info(description, api)

    def _plan(self, points: Sequence[Point], *, poll: bool) -> Plan:
        """Return the points' paths and types; a poll keeps them for the next poll.

        Kept per client for the points of the last poll only: a poll of the same points
        parses nothing again, however many, and nothing grows as points come and go.
        """
        listed = tuple(points)
        if poll and self._last is not None and self._last.points == listed:
            return self._last
        plan = Plan(listed)
        for point in listed:
            try:
                path, kind = parse_path(point.address), data_type(point.data_type)
            except PlcError as err:
                plan.errors[point] = PointResult(error=err.with_traceback(None))
                continue
            plan.want(point, path, kind)
        if poll:
            plan.clock = self._clock_path()
            if plan.clock is not None:
                plan.paths.setdefault(plan.clock.key, plan.clock)
            self._last = plan
        return plan

    async def _read(self, points: Sequence[Point], *, poll: bool) -> ReadResult:
        """Read every distinct path once: the poll's group, or variables for an on-demand read."""
        plan = self._plan(points, poll=poll)
        paths = plan.paths
        reader = self._poller()
        if not poll:
            reading = await reader.variables(list(paths.values()), {})
            return ReadResult(values=results(reading, plan, self._zone))
        clock_path = plan.clock
        reading = await reader.poll(paths) if paths else Reading()
        when = outcome(reading, clock_path, "DT", self._zone).value if clock_path else None
        status = plc_status(reader.crc, reader.regroups, when)
        return ReadResult(values=results(reading, plan, self._zone), status=status)

    async def _write(self, values: Mapping[Point, Value]) -> dict[Point, PointResult]:
        """Write every value with one PUT /variables; a refused variable fails alone."""
        items = [
            (point, parse_path(point.address), encode(data_type(point.data_type), v, self._zone))
            for point, v in values.items()
        ]
        results: dict[Point, PointResult] = {}
        await put(self._rest(), items, results)
        return {
            point: PointResult(value=value) if results[point].ok else results[point]
            for point, value in values.items()
        }

    async def browse(self) -> list[BrowseItem]:
        """List the HMI variables of the dictionary; expand structures and arrays to leaves."""
        api = self._rest()
        dictionary = await self._dictionary(DATA_DICTIONARY)
        variables = declared(dictionary)
        others = [variable for variable in variables if elementary(variable.type) is None]
        known: dict[str, dict[str, Any]] = {}
        values: dict[str, Any] = {}
        member_types: dict[str, str] = {}
        if others:
            try:
                known = types(await self._dictionary(TYPE_DICTIONARY))
            except PlcError as err:
                _LOGGER.debug("No type dictionary from %s: %s", self.config.host, err)
            reader = Reader(api)
            values = (await reader.variables([v.path for v in others], {})).found
            inside = [
                path
                for variable in others
                if variable.path.key in values
                for path in members(variable.path, values[variable.path.key], variable.type, known)
            ]
            member_types = await reader.types_of(inside)
        items: list[BrowseItem] = []
        for variable in variables:
            if elementary(variable.type) is None and variable.path.key not in values:
                continue
            items.extend(leaves(variable, values.get(variable.path.key), known, member_types))
        return items

    async def _dictionary(self, path: str) -> Any:
        """Fetch an eHMI dictionary (with the token, where the PLC asks for one)."""
        try:
            return await self._rest().call("GET", lambda _session: (path, None, None))
        except ApiError as err:
            raise request_error(err) from None

    def _clock_path(self) -> VariablePath | None:
        """Return the clock variable's path, when one is chosen."""
        clock = self._clock_point()
        return parse_path(clock.address) if clock else None

    def _clock_point(self) -> Point | None:
        """Return the clock variable's point, when one is chosen."""
        variable = str(self.config.options.get("clock_variable", "")).strip()
        return Point(variable, "DT") if variable else None

    @property
    def can_set_clock(self) -> bool:
        """True once a clock variable is chosen: the REST interface has no clock service."""
        return self._clock_point() is not None

    async def read_clock(self) -> datetime:
        """Return the clock variable's time (the PLC program keeps it)."""
        point = self._clock_point()
        if point is None:
            raise PlcProtocolError(
                "the REST interface has no clock service: choose the PLC's clock variable"
            )
        result = (await self._read([point], poll=False)).values[point]
        if result.error is not None:
            raise result.error
        assert isinstance(result.value, datetime)
        return result.value

    async def set_clock(self, when: datetime) -> None:
        """Write the time to the clock variable (a DT the PLC program copies into its clock)."""
        point = self._clock_point()
        if point is None:
            raise PlcWriteRefusedError(
                "the REST interface has no service that sets the PLC clock: choose a DT "
                "variable that the PLC program copies into its clock as the clock variable"
            )
        error = (await self.write({point: when}))[point].error
        if error is not None:
            raise error

    async def close(self) -> None:
        """Unregister the group and delete the session (best effort, briefly)."""
        if self._api is not None:
            await self._api.stop_keepalive()
            try:
                async with asyncio.timeout(CLOSE_TIMEOUT):
                    if self._reader is not None:
                        await self._reader.unregister_group()
                    await self._api.close_session()
            except (PlcError, TimeoutError) as err:
                _LOGGER.debug("Closing the session on %s failed: %s", self.config.host, err)
        self._api = None
        self._reader = None
        await self._close_own_session()
