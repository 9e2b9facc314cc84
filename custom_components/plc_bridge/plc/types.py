"""Vendor-neutral data types shared by every vendor client and by Home Assistant."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from datetime import datetime, timedelta
from enum import StrEnum
import re

from .errors import PlcError

SECRET_OPTION = re.compile(r"key|password|secret|token", re.IGNORECASE)
"""Vendor options whose values a repr masks (SoftPLC's client_key)."""
PATH_SEP = "\x1f"
"""Joins the names of a variable path in a footprint's area (no address or name holds it)."""

type Value = bool | int | float | str | datetime | timedelta | list[int]
"""A decoded point value: BOOL, integers, REAL, STRING, date/time, duration or raw bytes."""


class TlsMode(StrEnum):
    """How an HTTPS vendor checks the PLC's certificate."""

    VERIFY = "verify"  # against the system CAs
    PIN = "pin"  # the SHA-256 fingerprint the user confirmed at setup
    OFF = "off"  # no check at all (explicit; Home Assistant raises a repair issue)
    NONE = "none"  # plain HTTP or a non-TLS transport


class ValueKind(StrEnum):
    """What a point's values are, which decides the Home Assistant platforms that fit it."""

    BOOL = "bool"
    INTEGER = "integer"
    FLOAT = "float"
    TEXT = "text"
    DATETIME = "datetime"
    DURATION = "duration"  # a timedelta: S7 TIME, S5TIME, TIME_OF_DAY (since midnight)
    BYTES = "bytes"


@dataclass(frozen=True, slots=True, kw_only=True)
class ConnectionConfig:
    """Where and how to reach one PLC; `options` holds vendor-only settings (rack, slot, TSAP)."""

    host: str
    port: int
    username: str = ""
    password: str = ""
    tls: TlsMode = TlsMode.NONE
    fingerprint: str = ""  # hex SHA-256 of the DER certificate, for TlsMode.PIN
    timeout: float = 10.0
    time_zone: str = "UTC"  # IANA name of the zone the PLC clock runs in (Home Assistant's)
    poll_interval: float = 5.0  # seconds between two polls: a reconnect never waits longer
    options: dict[str, str | int | bool] = field(default_factory=dict)

    def __repr__(self) -> str:
        """Show the settings with the password and any secret option masked (logs, tracebacks)."""
        options = {
            key: "***" if value and SECRET_OPTION.search(key) else value
            for key, value in self.options.items()
        }
        return (
            f"ConnectionConfig(host={self.host!r}, port={self.port!r}, "
            f"username={self.username!r}, password={'***' if self.password else ''!r}, "
            f"tls={self.tls!r}, fingerprint={self.fingerprint!r}, timeout={self.timeout!r}, "
            f"time_zone={self.time_zone!r}, poll_interval={self.poll_interval!r}, "
            f"options={options!r})"
        )


@dataclass(frozen=True, slots=True)
class Point:
    """One value in the PLC: the address (or variable path) and the vendor's type or mode key."""

    address: str
    data_type: str


@dataclass(frozen=True, slots=True)
class Footprint:
    """The data a point covers: an area (or a name) and the range [start, end) within it."""

    area: str
    start: int
    end: int

    @classmethod
    def of_path(cls, parts: Iterable[str | int]) -> Footprint:
        """A named variable's footprint: it covers its elements and members too (`a` and `a.b`)."""
        return cls(PATH_SEP.join(str(part) for part in parts), 0, 1)

    def overlaps(self, other: Footprint) -> bool:
        """True when the two cover some of the same data, or one is a variable holding the other."""
        if self.area == other.area:
            return self.start < other.end and other.start < self.end
        return self.area.startswith(other.area + PATH_SEP) or other.area.startswith(
            self.area + PATH_SEP
        )


@dataclass(frozen=True, slots=True)
class PointResult:
    """The outcome for one point: a value, or the error that hides it."""

    value: Value | None = None
    error: PlcError | None = None

    @property
    def ok(self) -> bool:
        """True when the point was read or written without error."""
        return self.error is None


@dataclass(frozen=True, slots=True, kw_only=True)
class PlcStatus:
    """What the PLC reports about itself beside the values (for diagnostic entities)."""

    mode: str | None = None  # "RUN", "STOP", "HALT", ...
    system: str | None = None  # "OK", "Error", ...
    force: str | None = None  # "Forced", "Not Forced"
    clock: datetime | None = None
    extra: dict[str, str] = field(default_factory=dict)


@dataclass(frozen=True, slots=True, kw_only=True)
class ReadResult:
    """The answer to one poll: a result for every requested point, and the PLC status."""

    values: dict[Point, PointResult]
    status: PlcStatus = field(default_factory=PlcStatus)


@dataclass(frozen=True, slots=True, kw_only=True)
class DeviceInfo:
    """What the PLC says about itself at connect time."""

    vendor: str
    model: str
    serial: str | None = None  # unique id source where the vendor reports one
    mac: str | None = None
    firmware: str | None = None
    name: str | None = None
    can_write: bool = True
    extra: dict[str, str] = field(default_factory=dict)


@dataclass(frozen=True, slots=True, kw_only=True)
class BrowseItem:
    """A variable the PLC publishes, offered in the point form instead of typing an address."""

    address: str
    data_type: str
    name: str | None = None
    unit: str | None = None
    minimum: float | None = None
    maximum: float | None = None
    read_only: bool = False
    platform: str | None = None  # suggested Home Assistant platform, when the PLC says
    guessed: bool = False  # the PLC does not declare the type: it is guessed from the value


@dataclass(slots=True)
class ClientMetrics:
    """Request counters the client keeps for diagnostics and benchmarks."""

    requests: int = 0
    errors: int = 0
    session_renewals: int = 0  # re-logins after the PLC dropped the session or token
    polls: int = 0
    last_poll_requests: int = 0
    last_poll_ms: float = 0.0

    def as_dict(self) -> dict[str, float | int]:
        """Return the counters as a plain dict."""
        return {
            "requests": self.requests,
            "errors": self.errors,
            "session_renewals": self.session_renewals,
            "polls": self.polls,
            "last_poll_requests": self.last_poll_requests,
            "last_poll_ms": round(self.last_poll_ms, 3),
        }
