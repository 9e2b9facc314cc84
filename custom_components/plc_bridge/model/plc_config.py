"""The PLC as stored, typed: its connection, its poll options, its machines and its exposes.

One way in from storage: `PlcConfig.from_entry` (a config entry) and `PlcConfig.from_stored`
(what a pasted file holds, as `config_file.load_config` read it) give the same kind of object,
and `storage` gives back exactly what Home Assistant stores (entry data, options, subentries).

One validation: `problems` runs every rule the forms run on what is stored (the connection's
values, every address by the vendor's parser, each point by the point forms' own check, the parts
of each entity together, the write layout of the whole PLC, the poll intervals against the
vendor's pace, each expose by the expose form's check), each problem with the path of the stored
value it concerns. The doors word it their way: the pasted file on that value's line, the options
form on its field (`interval_problems`), the config flow's connection and reconfigure pages on
theirs (`Connection.problems`, and `file_problems` for certificate files).
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
import ipaddress
import re
from types import MappingProxyType
from typing import Any

from homeassistant.config_entries import ConfigEntry, ConfigSubentryData
from homeassistant.const import (
    CONF_HOST,
    CONF_NAME,
    CONF_PASSWORD,
    CONF_PORT,
    CONF_SCAN_INTERVAL,
    CONF_USERNAME,
)

from ..const import (
    CONF_ADDRESS,
    CONF_DATA_TYPE,
    CONF_FINGERPRINT,
    CONF_OPTIONS,
    CONF_PLATFORM,
    CONF_POINTS,
    CONF_READ_ONLY,
    CONF_ROLE,
    CONF_TLS,
    CONF_VENDOR,
    SUBENTRY_DEVICE,
    SUBENTRY_EXPOSE,
    SUBENTRY_POINT,
)
from ..plc import PlcClient, PlcError, PlcOptionError, PlcValueError, Point, TlsMode
from ..plc.vendors import client_class, implemented
from .availability import (
    CONF_AVAILABILITY_ADDRESS,
    CONF_AVAILABILITY_DATA_TYPE,
    CONF_AVAILABILITY_POLICY,
    check_policy,
    has_data_valid,
    policy_differs,
)
from .composite import (
    as_platform,
    group_errors,
    is_part,
    part_data,
    point_classes,
    supervision_data,
    travel_data,
)
from .expose import CONF_SEND, check_expose
from .kinds import CONF_SUPERVISION, CONF_TRAVEL_TIME
from .point_table import Describe, plain
from .points import PointConfig, point_data, read_only_errors
from .poll_classes import (
    CONF_FAST_INTERVAL,
    CONF_SLOW_INTERVAL,
    FAST,
    INTERVALS,
    NORMAL,
    SECONDS_MAX,
    SECONDS_MIN,
    class_minimums,
    interval_errors,
    unset,
)
from .write_rules import layout_conflicts
from .yaml_text import Path

ADDRESS_KEYS = (
    (CONF_ADDRESS, CONF_DATA_TYPE),
    (CONF_AVAILABILITY_ADDRESS, CONF_AVAILABILITY_DATA_TYPE),
)
"""The keys of an address and its data type, wherever they stand in a subentry's data."""
_EMPTY: Mapping[str, Any] = MappingProxyType({})


@dataclass(frozen=True, slots=True)
class Problem:
    """A stored value no form would store, where it stands, and how each door words it.

    `key` and `placeholders` are the pasted file's error (its line added by the door); `field`
    and `field_key` the form field and form error where a form shows the same problem.
    """

    path: Path
    key: str
    placeholders: Mapping[str, str] = _EMPTY
    field: str = ""
    field_key: str = ""


@dataclass(frozen=True, slots=True, kw_only=True)
class Connection:
    """The entry's data: how to reach the PLC. Keys not set stay unset when written back."""

    vendor: str
    host: str
    port: int
    tls: str = TlsMode.NONE.value
    fingerprint: str | None = None
    username: str | None = None
    password: str | None = None
    vendor_options: Mapping[str, Any] | None = None
    extra: Mapping[str, Any] = _EMPTY
    """Keys PLC Bridge stores beside these (a discovery's MAC), kept as they are."""
    has_tls: bool = True

    @classmethod
    def from_data(cls, data: Mapping[str, Any]) -> Connection:
        """Read the entry's data."""
        known = {
            CONF_VENDOR,
            CONF_HOST,
            CONF_PORT,
            CONF_TLS,
            CONF_FINGERPRINT,
            CONF_USERNAME,
            CONF_PASSWORD,
            CONF_OPTIONS,
        }
        options = data.get(CONF_OPTIONS)
        return cls(
            vendor=str(data[CONF_VENDOR]),
            host=str(data[CONF_HOST]),
            port=data[CONF_PORT],
            tls=str(data.get(CONF_TLS, TlsMode.NONE.value)),
            has_tls=CONF_TLS in data,
            fingerprint=data.get(CONF_FINGERPRINT),
            username=data.get(CONF_USERNAME),
            password=data.get(CONF_PASSWORD),
            vendor_options=None if options is None else MappingProxyType(dict(options)),
            extra=MappingProxyType({k: v for k, v in data.items() if k not in known}),
        )

    def to_data(self) -> dict[str, Any]:
        """Return the entry's data as stored."""
        data: dict[str, Any] = {CONF_VENDOR: self.vendor, CONF_HOST: self.host}
        data[CONF_PORT] = self.port
        if self.has_tls:
            data[CONF_TLS] = self.tls
        given = {
            CONF_FINGERPRINT: self.fingerprint,
            CONF_USERNAME: self.username,
            CONF_PASSWORD: self.password,
        }
        data |= {key: value for key, value in given.items() if value is not None}
        if self.vendor_options is not None:
            data[CONF_OPTIONS] = dict(self.vendor_options)
        return data | dict(self.extra)

    def problems(self) -> Iterator[Problem]:
        """Yield the values the connection pages would not take: address, then vendor options."""
        found = list(self.address_problems())
        yield from found
        if not found:
            yield from self.option_problems()

    def address_problems(self) -> Iterator[Problem]:
        """Yield the values of the first connection page it would not take: host, port, TLS."""
        where: Path = ("connection",)
        if self.vendor not in implemented():
            yield _bad_value((*where, CONF_VENDOR), CONF_VENDOR, ", ".join(implemented()))
            return
        if not host_valid(self.host):
            yield _bad_value((*where, CONF_HOST), CONF_HOST, HOST_KIND)
        if (
            isinstance(self.port, bool)
            or not isinstance(self.port, int)
            or not 1 <= self.port <= 65535
        ):
            yield _bad_value((*where, CONF_PORT), CONF_PORT, "a whole number from 1 to 65535")
        modes = [mode.value for mode in client_class(self.vendor).tls_modes]
        if self.has_tls and self.tls not in modes:
            yield _bad_value((*where, CONF_TLS), CONF_TLS, ", ".join(modes))

    def option_problems(self) -> Iterator[Problem]:
        """Yield the vendor option the vendor's client refuses (`validate_options`), if any."""
        try:
            client_class(self.vendor).validate_options(self.vendor_options or {})
        except PlcValueError as err:
            option = err.option if isinstance(err, PlcOptionError) else ""
            yield Problem(
                ("connection", CONF_OPTIONS, *((option,) if option else ())),
                "config_connection_option",
                {"name": option or CONF_OPTIONS, "problem": str(err)},
                option,
                "invalid_options",
            )


HOST_KIND = "a host name or IP address alone (no http://, path or port)"
_LABEL = re.compile(r"[^\W_][\w-]{0,62}")
"""A label of a host name: letters (any script), digits, hyphens and underscores."""


def host_valid(host: str) -> bool:
    """True for a host name or an IP address alone: no scheme, path, port or user."""
    if not host or host != host.strip() or len(host) > 253:
        return False
    try:
        ipaddress.ip_address(host)
    except ValueError:
        pass
    else:
        return True
    return all(_LABEL.fullmatch(label) for label in host.removesuffix(".").split("."))


def file_problems(
    vendor: str, folder: str, submitted: Mapping[str, Any], stored: Mapping[str, Any]
) -> tuple[dict[str, str], list[Problem]]:
    """Return the options naming files, resolved in the configuration folder, or their problem.

    Blocking (an executor's work). A file outside the folder, missing or not a PEM pair is
    refused on its option, in the pasted file and on the connection page alike.
    """
    try:
        return client_class(vendor).resolve_options(folder, submitted, stored), []
    except PlcOptionError as err:
        key = "pem_outside_config" if err.outside else "invalid_pem"
        placeholders = {"name": err.option, "problem": str(err)}
        path: Path = ("connection", CONF_OPTIONS, err.option)
        return {}, [Problem(path, "config_option", placeholders, err.option, key)]


def _bad_value(path: Path, name: str, kind: str) -> Problem:
    """Return the problem of a value that is not of its key's kind, on its form field."""
    return Problem(path, "config_bad_value", {"name": name, "kind": kind}, name, f"invalid_{name}")


@dataclass(frozen=True, slots=True, kw_only=True)
class PollOptions:
    """The entry's options: its poll intervals in seconds (None: not set, the default applies)."""

    scan_interval: float | None = None
    fast_interval: float | None = None
    slow_interval: float | None = None
    extra: Mapping[str, Any] = _EMPTY

    @classmethod
    def from_options(cls, options: Mapping[str, Any]) -> PollOptions:
        """Read the entry's options."""
        return cls(
            scan_interval=options.get(CONF_SCAN_INTERVAL),
            fast_interval=options.get(CONF_FAST_INTERVAL),
            slow_interval=options.get(CONF_SLOW_INTERVAL),
            extra=MappingProxyType({k: v for k, v in options.items() if k not in INTERVALS}),
        )

    def to_options(self) -> dict[str, Any]:
        """Return the entry's options as stored."""
        given = {
            CONF_FAST_INTERVAL: self.fast_interval,
            CONF_SCAN_INTERVAL: self.scan_interval,
            CONF_SLOW_INTERVAL: self.slow_interval,
        }
        return {key: value for key, value in given.items() if value is not None} | dict(self.extra)

    @property
    def intervals(self) -> dict[str, float]:
        """The intervals set, in seconds, by option key."""
        return {key: float(value) for key, value in self.to_options().items() if key in INTERVALS}


@dataclass(frozen=True, slots=True, kw_only=True)
class Subentry:
    """One subentry as stored: a machine (device), an expose, or a version 1 point.

    `at` is where it stands in the paths of problems: its subentry id in an entry, its index
    in a pasted file.
    """

    at: str | int
    subentry_type: str
    title: str
    unique_id: str | None
    data: Mapping[str, Any]

    @property
    def path(self) -> Path:
        """The path of its data."""
        return ("subentries", self.at, "data")

    def points(self) -> list[tuple[str, Mapping[str, Any], Path]]:
        """Return its points: id, data (a version 1 point's with its name) and path."""
        if self.subentry_type == SUBENTRY_POINT:
            return [("", {CONF_NAME: self.title, **self.data}, self.path)]
        if self.subentry_type != SUBENTRY_DEVICE:
            return []
        points = self.data.get(CONF_POINTS) or {}
        return [
            (str(point_id), data, (*self.path, CONF_POINTS, point_id))
            for point_id, data in points.items()
            if isinstance(data, Mapping) and CONF_ADDRESS in data and CONF_DATA_TYPE in data
        ]

    @property
    def availability(self) -> Point | None:
        """A machine's data-valid address, if it names one."""
        data = self.data
        if self.subentry_type != SUBENTRY_DEVICE or not data.get(CONF_AVAILABILITY_ADDRESS):
            return None
        address, data_type = data[CONF_AVAILABILITY_ADDRESS], data.get(CONF_AVAILABILITY_DATA_TYPE)
        return Point(str(address), str(data_type or ""))

    def stored(self) -> ConfigSubentryData:
        """Return the subentry as Home Assistant creates it."""
        return ConfigSubentryData(
            data=dict(self.data),
            subentry_type=self.subentry_type,
            title=self.title,
            unique_id=self.unique_id,
        )


@dataclass(frozen=True, slots=True, kw_only=True)
class PlcConfig:
    """One PLC as stored: connection, poll options, and its subentries in their order."""

    title: str
    version: int
    minor_version: int
    connection: Connection
    options: PollOptions
    subentries: tuple[Subentry, ...] = field(default=())

    @classmethod
    def from_entry(cls, entry: ConfigEntry[Any]) -> PlcConfig:
        """Read a config entry."""
        return cls(
            title=entry.title,
            version=entry.version,
            minor_version=entry.minor_version,
            connection=Connection.from_data(entry.data),
            options=PollOptions.from_options(entry.options),
            subentries=tuple(
                Subentry(
                    at=subentry.subentry_id,
                    subentry_type=subentry.subentry_type,
                    title=subentry.title,
                    unique_id=subentry.unique_id,
                    data=subentry.data,
                )
                for subentry in entry.subentries.values()
            ),
        )

    @classmethod
    def from_stored(
        cls,
        *,
        title: str,
        version: int,
        minor_version: int,
        data: Mapping[str, Any],
        options: Mapping[str, Any],
        subentries: Sequence[ConfigSubentryData],
    ) -> PlcConfig:
        """Read what an entry would store (a pasted file: `ConfigFile.plc`); subentries by index."""
        return cls(
            title=title,
            version=version,
            minor_version=minor_version,
            connection=Connection.from_data(data),
            options=PollOptions.from_options(options),
            subentries=tuple(
                Subentry(
                    at=index,
                    subentry_type=subentry["subentry_type"],
                    title=subentry["title"],
                    unique_id=subentry["unique_id"],
                    data=subentry["data"],
                )
                for index, subentry in enumerate(subentries)
            ),
        )

    def storage(self) -> tuple[dict[str, Any], dict[str, Any], list[ConfigSubentryData]]:
        """Return what Home Assistant stores: entry data, options and subentries."""
        return (
            self.connection.to_data(),
            self.options.to_options(),
            [subentry.stored() for subentry in self.subentries],
        )

    def point_configs(self) -> dict[str, PointConfig]:
        """Return every point of its machines, by point id."""
        return {
            point_id: PointConfig(point_id, str(subentry.at), data)
            for subentry in self.subentries
            if subentry.subentry_type == SUBENTRY_DEVICE
            for point_id, data, _ in subentry.points()
        }

    def availability_points(self) -> list[Point]:
        """Return the data-valid address of every machine that names one (read at every poll)."""
        return [point for sub in self.subentries if (point := sub.availability) is not None]

    def read_only_points(self) -> list[Point]:
        """Return the points of its machines Home Assistant never writes."""
        return [
            Point(str(data[CONF_ADDRESS]), str(data[CONF_DATA_TYPE]))
            for subentry in self.subentries
            for _, data, _ in subentry.points()
            if data.get(CONF_READ_ONLY)
        ]

    def poll_minimums(self, client: type[PlcClient]) -> tuple[dict[str, float], list[Point]]:
        """Return the shortest interval of each poll class the vendor's pace allows, and points.

        The points are those of the machines, each once (their data-valid addresses aside).
        """
        configs = self.point_configs()
        every_poll = self.availability_points()
        points = list(dict.fromkeys(config.point for config in configs.values()))
        polled = list(dict.fromkeys([*every_poll, *points]))
        classes = point_classes(configs, every_poll)
        return class_minimums(client, classes, polled), points

    def interval_problems(
        self, client: type[PlcClient], given: Mapping[str, float] | None = None
    ) -> list[Problem]:
        """Return the poll intervals (`given`, else the stored ones) the options form refuses."""
        stored = self.options.intervals
        intervals = dict(stored if given is None else given)
        minimums, _ = self.poll_minimums(client)
        problems = [
            Problem(
                ("options", key),
                "config_interval",
                {"name": key, "minimum": f"{SECONDS_MIN:g}"},
                key,
                "interval_out_of_range",
            )
            for key, value in intervals.items()
            if not SECONDS_MIN <= value <= SECONDS_MAX  # the form's own field bounds
        ]
        if problems:
            return problems
        errors = interval_errors(unset(client, intervals, minimums), minimums)
        return [
            Problem(
                ("options", key if key in intervals else CONF_SCAN_INTERVAL),
                "config_interval",
                {
                    "name": key,
                    "minimum": f"{minimums[FAST if key == CONF_FAST_INTERVAL else NORMAL]:g}",
                },
                key,
                error,
            )
            for key, error in errors.items()
        ]

    def problems(self, client: type[PlcClient], describe: Describe = plain) -> list[Problem]:
        """Return what no form would store, in the order the forms would meet it.

        Addresses come first: the checks after them read only points the parser took.
        """
        found = [*self.connection.problems(), *self._address_problems(client)]
        if found:
            return found
        found = self._point_problems(client, describe)
        return found or [*self.interval_problems(client), *self._expose_problems(client)]

    def _address_problems(self, client: type[PlcClient]) -> Iterator[Problem]:
        """Yield each address the vendor's parser refuses, with what it belongs to."""
        for subentry in self.subentries:
            for name, point, path in _addressed(subentry.data, subentry.title, subentry.path):
                try:
                    client.validate_point(point)
                except PlcError as err:
                    yield Problem(
                        path,
                        "config_bad_address",
                        {"point": name, "address": point.address, "problem": str(err)},
                        path[-1] if isinstance(path[-1], str) else "",
                        "invalid_address",
                    )

    def _point_problems(self, client: type[PlcClient], describe: Describe) -> list[Problem]:
        """Return the points the point forms refuse and the entities their parts do not make.

        Without those: the writes the layout of the whole PLC would refuse.
        """
        placed = [(data, path) for sub in self.subentries for _, data, path in sub.points()]
        problems = [
            problem for data, path in placed for problem in _point(client, data, path, describe)
        ]
        for subentry in self.subentries:
            points = subentry.points()
            problems += _policy_problems(subentry, points)
            for name, key, details in group_errors([data for _, data, _ in points]):
                path = next(path for _, data, path in points if data.get(CONF_NAME) == name)
                problems.append(
                    Problem(path, "config_entity", {"problem": describe(key, details)}, "", key)
                )
        if problems:
            return problems
        paths = {id(data): path for data, path in placed}
        for data, conflict in layout_conflicts(client, [], [data for data, _ in placed]):
            key = (
                "config_writes_read_only"
                if conflict.key == "writes_read_only"
                else "config_overlap"
            )
            other = conflict.other.address if conflict.other else ""
            placeholders = {
                "point": _named(data),
                "address": conflict.point.address,
                "other": other,
            }
            path = (*paths[id(data)], CONF_ADDRESS)
            problems.append(Problem(path, key, placeholders, CONF_ADDRESS, conflict.key))
        return problems

    def _expose_problems(self, client: type[PlcClient]) -> Iterator[Problem]:
        """Yield each expose value its form refuses.

        Its feedback is checked when it is turned on: the entities it would follow do not
        exist before the PLC is added.
        """
        for subentry, _, errors, words in self._checked_exposes(client):
            for name, key in errors.items():
                yield Problem(
                    (*subentry.path, name),
                    f"config_expose_{key}",
                    {"point": subentry.title, **words},
                    name,
                    key,
                )

    def sending_off(self, client: type[PlcClient]) -> list[ConfigSubentryData]:
        """Return the subentries to create, each expose as its form stores it, sending off."""
        exposes = {id(sub): data for sub, data, _, _ in self._checked_exposes(client)}
        return [
            subentry.stored()
            if id(subentry) not in exposes
            else ConfigSubentryData(
                data=exposes[id(subentry)] | {CONF_SEND: False},
                subentry_type=SUBENTRY_EXPOSE,
                title=subentry.title,
                unique_id=subentry.unique_id,
            )
            for subentry in self.subentries
        ]

    def _checked_exposes(
        self, client: type[PlcClient]
    ) -> Iterator[tuple[Subentry, dict[str, Any], dict[str, str], dict[str, str]]]:
        """Yield each expose checked by the expose form's one check.

        Against the read-only points, and the addresses of the exposes before it.
        """
        read_only = self.read_only_points()
        taken: list[Point] = []
        for subentry in self.subentries:
            if subentry.subentry_type != SUBENTRY_EXPOSE:
                continue
            data, errors, words = check_expose(
                client, subentry.data, read_only=read_only, taken=taken
            )
            yield subentry, data, errors, words
            taken.append(
                Point(str(subentry.data[CONF_ADDRESS]), str(subentry.data[CONF_DATA_TYPE]))
            )


def _point(
    client: type[PlcClient], data: Mapping[str, Any], path: Path, describe: Describe
) -> Iterator[Problem]:
    """Yield the first problem the point forms find in one stored point.

    A command stored read only, and a travel or supervision time out of bounds or on an entity
    without one, have the file's own words; the rest the point form's (`point_data`, a part's
    `part_data`).
    """
    platform, role = str(data.get(CONF_PLATFORM, "")), str(data.get(CONF_ROLE) or "")
    name = _named(data)
    errors = read_only_errors(as_platform(platform, role), role, bool(data.get(CONF_READ_ONLY)))
    if errors:
        placeholders = {"point": name, "address": str(data[CONF_ADDRESS])}
        yield Problem(
            (*path, CONF_READ_ONLY),
            "config_command_read_only",
            placeholders,
            CONF_READ_ONLY,
            errors[CONF_READ_ONLY],
        )
        return
    if wrong := travel_data(platform, data)[1]:
        key = next(iter(wrong.values()))
        yield Problem(
            (*path, CONF_TRAVEL_TIME), "config_travel_time", {"point": name}, CONF_TRAVEL_TIME, key
        )
        return
    if wrong := supervision_data(platform if is_part(platform, role) else "", data)[1]:
        key = next(iter(wrong.values()))
        yield Problem(
            (*path, CONF_SUPERVISION), "config_supervision", {"point": name}, CONF_SUPERVISION, key
        )
        return
    _, errors, details = (part_data if is_part(platform, role) else point_data)(client, data)
    if errors:
        field_name, key = next(iter(errors.items()))
        yield Problem(
            (*path, field_name),
            "config_point",
            {"point": name, "problem": describe(key, details)},
            field_name,
            key,
        )


def _policy_problems(
    subentry: Subentry, points: list[tuple[str, Mapping[str, Any], Path]]
) -> list[Problem]:
    """Return the availability policies the forms refuse.

    Unknown ones, one following a data-valid address the machine does not name, and parts of
    one entity that differ.
    """
    data_valid = has_data_valid(subentry.data)
    problems = [
        Problem(
            (*path, CONF_AVAILABILITY_POLICY),
            "config_availability_policy",
            {"point": _named(data)},
            CONF_AVAILABILITY_POLICY,
            key,
        )
        for _, data, path in points
        if (key := check_policy(data, data_valid=data_valid)[1])
    ]
    for name in policy_differs(data for _, data, _ in points)[:1]:
        path = next(path for _, data, path in points if data.get(CONF_NAME) == name)
        problems.append(
            Problem(
                (*path, CONF_AVAILABILITY_POLICY),
                "config_availability_policy",
                {"point": name},
                CONF_AVAILABILITY_POLICY,
                "availability_policy_differs",
            )
        )
    return problems


def _named(data: Mapping[str, Any]) -> str:
    """Return a point's name for a message: its entity's name and, for a part, its role."""
    role = data.get(CONF_ROLE)
    return f"{data.get(CONF_NAME, '')} ({role})" if role else str(data.get(CONF_NAME, ""))


def _addressed(value: Any, name: str, path: Path) -> Iterator[tuple[str, Point, Path]]:
    """Yield every point a value names, with the name of what it belongs to and its path.

    A point is an address and a data type, or a machine's availability address and its type.
    """
    if isinstance(value, Mapping):
        for address, data_type in ADDRESS_KEYS:
            if address in value and data_type in value:
                point = Point(str(value[address]), str(value[data_type]))
                yield str(value.get(CONF_NAME) or name), point, (*path, address)
        for key, item in value.items():
            named = f"{name} {key}" if key != CONF_POINTS else name
            yield from _addressed(item, named, (*path, key))
    elif isinstance(value, Sequence) and not isinstance(value, str):
        for index, item in enumerate(value):
            yield from _addressed(item, name, (*path, index))
