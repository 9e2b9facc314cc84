"""One ISO-on-TCP (RFC 1006) connection: TSAPs from the options, the S7 session, one choke point.

python-snap7 does the framing: `AsyncISOTCPConnection` (asyncio streams, TPKT/COTP) and
`S7Protocol` (setup, SZL, clock PDUs; reply parsing). Every request goes through `exchange`,
which counts it, bounds it with the timeout and maps errors; no thread, no executor.

A reply may come in several COTP data frames (ISO 8073 lets a CPU lower the TPDU size): they
are joined until the frame marked last (EOT), and a reply that grows past the negotiated PDU
without one is a protocol error, never a wait for more.

A CPU, CP or firewall may close a connection left idle (simulators/s7/READINGS.md, row 17). A
connection the PLC is known to have closed before a request is sent (its FIN already in) is
renewed first, for any request. A read found closed only by sending it (EOF or reset before any
byte of the reply) is sent once more on a renewed connection; a write never is: it fails, since
the PLC may have done it before closing. A renewal keeps what the link learned (same host and
TSAP) unless the PLC negotiates another PDU size, which fails the request as a lost connection.
"""

from __future__ import annotations

import asyncio
from collections.abc import Mapping
import contextlib
from dataclasses import dataclass
from datetime import datetime
import logging
import re
import struct
from typing import Any

from snap7.async_client import AsyncISOTCPConnection
from snap7.error import S7ConnectionError, S7ProtocolError, S7TimeoutError
from snap7.s7protocol import S7Protocol, S7UserDataGroup, S7UserDataSubfunction

from ...errors import (
    PlcConnectionError,
    PlcError,
    PlcOptionError,
    PlcProtocolError,
    PlcSessionRefusedError,
    PlcTimeoutError,
)
from ...types import ClientMetrics
from .planner import DEFAULT_PDU, Span, WriteItem
from .protocol import read_items, read_request, write_codes, write_request

_LOGGER = logging.getLogger(__name__)
SHOWN = 120
"""Bytes of a PDU a debug line shows (S7 carries no credentials)."""

PG = 0x01  # connection type in a rack/slot TSAP, as Snap7 connects by default
LOCAL_TSAP = 0x0100
MAX_FRAGMENTS = 16
COTP_DT, COTP_DR, EOT = 0xF0, 0x80, 0x80  # data, disconnect request; "last frame" bit of a DT
FAMILIES = ("s7_300_1500", "s7_200")  # the first is the default
_TSAP = re.compile(r"([0-9A-F]{1,2})\.([0-9A-F]{1,2})|0X([0-9A-F]{1,4})")
_DIGITS = re.compile(r"[0-9]{1,3}")  # ASCII only: "²".isdigit() is true, int("²") raises


class S7RequestError(PlcProtocolError):
    """The PLC answered a request with an error (the connection itself is fine)."""

    def __init__(self, message: str, code: int | None = None) -> None:
        super().__init__(message)
        self.code = code


@dataclass(frozen=True, slots=True)
class Endpoint:
    """The TSAP pair of a connection, ours (calling) and the PLC's (called); the CPU family."""

    local_tsap: int
    remote_tsap: int
    s7_200: bool = False  # an S7-200 with a CP 243-1: timers and counters on 0x1F/0x1E


def _shown(value: object) -> str:
    """Return an option value as a message shows it: its repr, cut short."""
    text = repr(value) if not isinstance(value, int) or abs(value) < 10**40 else "a huge number"
    return text if len(text) <= 40 else f"{text[:37]}..."


def parse_tsap(value: object, what: str) -> int:
    """Return a TSAP from "10.01" (as STEP 7 writes it), "0x1001" or an int."""
    if isinstance(value, int) and not isinstance(value, bool) and 0 <= value <= 0xFFFF:
        return value
    match = _TSAP.fullmatch(value.strip().upper()) if isinstance(value, str) else None
    if match is None:
        raise PlcOptionError(
            f"{what} {_shown(value)} is not a TSAP; write it as STEP 7 does, e.g. 10.01", what
        )
    if match[3]:
        return int(match[3], 16)
    return int(match[1], 16) << 8 | int(match[2], 16)


def tsap_text(tsap: int) -> str:
    """Return a TSAP as STEP 7 writes it (0x1001 -> "10.01")."""
    return f"{tsap >> 8:02X}.{tsap & 0xFF:02X}"


def _number(options: Mapping[str, object], key: str, default: int, high: int) -> int:
    """Return a small whole number option (form numbers may come as floats or text)."""
    value = options.get(key, default)
    if isinstance(value, str) and _DIGITS.fullmatch(value.strip()):
        value = int(value)
    if isinstance(value, float) and value.is_integer() and abs(value) <= high + 1:
        value = int(value)
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= high:
        raise PlcOptionError(
            f"{key} must be a whole number from 0 to {high}, not {_shown(value)}", key
        )
    return value


def validate_options(options: Mapping[str, object]) -> dict[str, str | int | bool]:
    """Return the connection options normalized; raise PlcOptionError naming the field at fault.

    "connection": "rack_slot" (default: "rack" 0..7, "slot" 0..31) or "tsap" ("local_tsap",
    default 01.00, and "remote_tsap", e.g. 10.00/10.01 for an S7-200 CP 243-1). "family":
    "s7_300_1500" (default: S7-300/400/1200/1500) or "s7_200" (S7-200 with a CP 243-1, whose
    timers and counters have area codes of their own). Other keys are left out.
    """
    family = options.get("family", FAMILIES[0])
    if family not in FAMILIES:
        raise PlcOptionError(
            f"family must be one of {', '.join(FAMILIES)}, not {_shown(family)}", "family"
        )
    connection = options.get("connection", "rack_slot")
    if connection == "rack_slot":
        rack, slot = _number(options, "rack", 0, 7), _number(options, "slot", 1, 31)
        return {"connection": "rack_slot", "rack": rack, "slot": slot, "family": str(family)}
    if connection == "tsap":
        if options.get("remote_tsap") in (None, ""):
            raise PlcOptionError(
                "remote_tsap is needed to connect by TSAP, e.g. 10.01", "remote_tsap"
            )
        local = parse_tsap(options.get("local_tsap", LOCAL_TSAP), "local_tsap")
        remote = parse_tsap(options["remote_tsap"], "remote_tsap")
        return {
            "connection": "tsap",
            "local_tsap": tsap_text(local),
            "remote_tsap": tsap_text(remote),
            "family": str(family),
        }
    raise PlcOptionError(
        f"connection must be 'rack_slot' or 'tsap', not {_shown(connection)}", "connection"
    )


def endpoint(options: Mapping[str, object]) -> Endpoint:
    """Return the TSAP pair (rack/slot: PG connection 01.xx) and family the options ask for."""
    settings = validate_options(options)
    s7_200 = settings["family"] == "s7_200"
    if settings["connection"] == "tsap":
        local = parse_tsap(settings["local_tsap"], "local_tsap")
        return Endpoint(local, parse_tsap(settings["remote_tsap"], "remote_tsap"), s7_200)
    rack, slot = int(settings["rack"]), int(settings["slot"])
    return Endpoint(LOCAL_TSAP, PG << 8 | rack << 5 | slot, s7_200)


class _ClosedByPeerError(PlcConnectionError):
    """The PLC closed the connection before any byte of the reply: a read may be sent again."""


class _Connection(AsyncISOTCPConnection):
    """python-snap7's ISO-on-TCP connection: replies joined from frames, a close by the peer told.

    `tcp_opened` says whether TCP was open when the ISO step began: a CPU that refuses the TSAP
    (a wrong slot) has taken the TCP connection, which tells a wrong slot or TSAP from a wrong
    host or port without a second connection to probe the port.
    """

    tcp_opened = False
    limit = DEFAULT_PDU  # the most bytes a reply may take: the PDU size, once negotiated

    async def _iso_connect(self) -> None:
        """Note the open TCP connection, then send the COTP connection request."""
        self.tcp_opened = True
        await super()._iso_connect()

    @property
    def peer_closed(self) -> bool:
        """True once the PLC has closed its side (nothing more can come from it)."""
        return self._reader is not None and self._reader.at_eof()

    async def send_data(self, data: bytes) -> None:
        """Send one S7 PDU; a connection that fails the sending was closed by the PLC."""
        try:
            await super().send_data(data)
        except S7ConnectionError as err:
            raise _ClosedByPeerError(f"the PLC closed the connection: {err}") from err

    async def receive_data(self) -> bytes:
        """Return one S7 PDU, joined from COTP data frames up to the one marked last (EOT)."""
        parts: list[bytes] = []
        size = 0
        while True:
            head = await self._frame_bytes(4, first=not parts)
            version, _, length = struct.unpack(">BBH", head)
            if version != 3 or length < 7:
                raise S7ConnectionError(f"invalid TPKT header {head.hex(' ')}")
            payload = await self._frame_bytes(length - 4, first=False)
            if payload[1] == COTP_DR and not parts:
                raise _ClosedByPeerError("the PLC disconnected (COTP disconnect request)")
            if payload[0] != 2 or payload[1] != COTP_DT or payload[2] & 0x7F:
                raise S7ConnectionError(f"expected a COTP data frame, got {payload[:3].hex(' ')}")
            parts.append(payload[3:])
            size += len(payload) - 3
            if size > self.limit or len(parts) > self.limit:
                raise PlcProtocolError(
                    f"the PLC's reply passed {self.limit} bytes (the PDU size) in {len(parts)} "
                    "frames without the frame marked last"
                )
            if payload[2] & EOT:
                return b"".join(parts)

    async def _frame_bytes(self, size: int, *, first: bool) -> bytes:
        """Return `size` bytes of a reply; EOF or reset before its first byte: the PLC closed."""
        if self._reader is None:
            raise S7ConnectionError("Not connected")
        try:
            return await self._reader.readexactly(size)
        except asyncio.IncompleteReadError as err:
            self.connected = False
            if first and not err.partial:
                raise _ClosedByPeerError("the PLC closed the connection") from None
            raise S7ConnectionError(
                "the PLC closed the connection in the middle of a reply"
            ) from None
        except OSError as err:
            self.connected = False
            if first:
                raise _ClosedByPeerError(f"the PLC closed the connection: {err}") from err
            raise S7ConnectionError(
                f"the connection broke in the middle of a reply: {err}"
            ) from err


class S7Link:
    """An open S7 session; unusable once an exchange broke it (the client then opens another)."""

    def __init__(
        self, host: str, port: int, ends: Endpoint, timeout: float, metrics: ClientMetrics
    ) -> None:
        """Prepare the connection; nothing is sent until `open`."""
        self._address = (host, port, ends)
        self._connection = self._new_connection()
        self._where = f"{host}:{port} (TSAP {tsap_text(ends.remote_tsap)})"
        self._protocol = S7Protocol()
        self._timeout = timeout
        self._metrics = metrics
        self._broken = False
        self._requested_pdu = DEFAULT_PDU
        self.pdu_size = DEFAULT_PDU

    def _new_connection(self) -> _Connection:
        """Return an unopened ISO-on-TCP connection to the PLC."""
        host, port, ends = self._address
        return _Connection(host, port, ends.local_tsap, ends.remote_tsap)

    @property
    def usable(self) -> bool:
        """True while the session can carry requests."""
        return self._connection.connected and not self._broken

    async def open(self, requested_pdu: int) -> None:
        """Connect (TCP, COTP with the TSAPs) and negotiate the PDU size."""
        self._requested_pdu = requested_pdu
        self.pdu_size = await self._start()

    async def _start(self) -> int:
        """Open the connection and set up the S7 session; return the PDU size agreed."""
        try:
            await self._connection.connect(timeout=self._timeout)
        except S7TimeoutError as err:
            raise PlcTimeoutError(
                f"{self._where} did not answer within {self._timeout:g} s"
            ) from err
        except S7ConnectionError as err:
            refused = self._connection.tcp_opened
            error = PlcSessionRefusedError if refused else PlcConnectionError
            raise error(f"cannot connect to {self._where}: {err}") from err
        try:
            request = self._protocol.build_setup_communication_request(1, 1, self._requested_pdu)
            response = await self._round_trip(request)
            pdu = (response.get("parameters") or {}).get("pdu_length")
            if not isinstance(pdu, int) or pdu < 64:
                raise PlcProtocolError(f"the PLC negotiated an unusable PDU size {pdu!r}")
        except S7RequestError as err:
            await self.close()
            raise PlcSessionRefusedError(f"the PLC refused the S7 session: {err}") from err
        except PlcError:
            await self.close()
            raise
        self._connection.limit = min(pdu, self._requested_pdu)
        return self._connection.limit

    async def _renew(self) -> None:
        """Open a new connection in place of the one the PLC closed; the same PDU size or fail."""
        _LOGGER.debug("The S7 PLC %s closed the connection; opening a new one", self._where)
        with contextlib.suppress(Exception):
            async with asyncio.timeout(self._timeout):
                await self._connection.disconnect()
        self._connection = self._new_connection()
        self._broken = False
        self._metrics.session_renewals += 1
        try:
            pdu = await self._start()
        except PlcError:
            self._broken = True
            raise
        if pdu != self.pdu_size:
            await self.close()
            raise PlcConnectionError(
                f"the PLC came back with a PDU of {pdu} bytes instead of {self.pdu_size}"
            )

    async def exchange(self, request: bytes, *, resend: bool = False) -> dict[str, Any]:
        """Send one S7 PDU and return its answer parsed (the choke point).

        A connection the PLC closed is renewed first; `resend` (reads only) sends the request
        once more on a renewed connection when the PLC closed it before any byte of the reply.
        """
        if not self.usable:
            raise PlcConnectionError("the connection to the PLC is closed")
        if self._connection.peer_closed:
            await self._renew()
        try:
            return await self._round_trip(request)
        except _ClosedByPeerError as err:
            if not resend:
                raise PlcConnectionError(
                    f"{err} before answering; a write is not sent again (it may have been done)"
                ) from err
        await self._renew()
        return await self._round_trip(request)

    async def _round_trip(self, request: bytes) -> dict[str, Any]:
        """Send one S7 PDU, wait for its answer within the timeout and parse it."""
        self._metrics.requests += 1
        try:
            async with asyncio.timeout(self._timeout):
                await self._connection.send_data(request)
                reply = await self._connection.receive_data()
            _LOGGER.debug("S7 request %s -> reply %s", request[:SHOWN].hex(), reply[:SHOWN].hex())
        except asyncio.CancelledError:
            self._broken = True  # an answer may still be on its way: never reuse the stream
            raise
        except (TimeoutError, S7TimeoutError) as err:
            self._broken = True
            raise PlcTimeoutError(f"the PLC did not answer within {self._timeout:g} s") from err
        except PlcError:
            self._broken = True
            raise
        except (S7ConnectionError, OSError) as err:
            self._broken = True
            raise PlcConnectionError(f"the connection to the PLC broke: {err}") from err
        if reply[4:6] != request[4:6]:
            self._broken = True
            raise PlcProtocolError("the PLC answered another request than the one sent")
        try:
            return self._protocol.parse_response(reply)
        except S7ProtocolError as err:
            raise S7RequestError(str(err), err.error_code) from None

    def _sequence(self) -> int:
        """Return the next PDU reference (shared with the library's builders)."""
        self._protocol.sequence = (self._protocol.sequence + 1) & 0xFFFF
        return self._protocol.sequence

    async def read(self, spans: list[Span]) -> list[bytes | int]:
        """Read several items in one request: their data, or their return codes."""
        response = await self.exchange(read_request(self._sequence(), spans), resend=True)
        return read_items(response, len(spans))

    async def write(self, items: list[WriteItem]) -> list[int]:
        """Write several items in one request; return their return codes."""
        response = await self.exchange(write_request(self._sequence(), items))
        return write_codes(response, len(items))

    def _checked(self, response: dict[str, Any], group: int, sub: int, *, empty: bool) -> None:
        """Check a USERDATA answer is a success of the expected function."""
        try:
            self._protocol.check_userdata_response(response, group, sub, accept_null_ack=empty)
        except S7ProtocolError as err:
            raise S7RequestError(str(err), err.error_code) from None

    async def read_szl(self, szl_id: int, index: int = 0) -> bytes:
        """Read a system status list (header and records), following up on fragments."""
        request = self._protocol.build_read_szl_request(szl_id, index)
        response = await self.exchange(request, resend=True)
        group, sub = S7UserDataGroup.SZL, S7UserDataSubfunction.READ_SZL
        self._checked(response, group, sub, empty=False)
        data = self._protocol.parse_read_szl_response(response)["data"]
        for _ in range(MAX_FRAGMENTS):
            parameters = response.get("parameters") or {}
            if not parameters.get("last_data_unit"):
                return bytes(data)
            followup = self._protocol.build_userdata_followup_request(
                group, sub, parameters.get("sequence_number", 0)
            )
            response = await self.exchange(followup, resend=True)
            self._checked(response, group, sub, empty=False)
            data += self._protocol.parse_read_szl_response(response, first_fragment=False)["data"]
        raise PlcProtocolError(f"SZL 0x{szl_id:04X} came in more than {MAX_FRAGMENTS} fragments")

    async def get_clock(self) -> datetime:
        """Return the PLC clock (naive, PLC local time)."""
        response = await self.exchange(self._protocol.build_get_clock_request(), resend=True)
        self._checked(response, S7UserDataGroup.TIME, S7UserDataSubfunction.GET_CLOCK, empty=False)
        try:
            return self._protocol.parse_get_clock_response(response)
        except S7ProtocolError as err:
            raise PlcProtocolError(str(err)) from None

    async def set_clock(self, when: datetime) -> None:
        """Set the PLC clock (naive, PLC local time, years 1990..2089)."""
        response = await self.exchange(self._protocol.build_set_clock_request(when))
        self._checked(response, S7UserDataGroup.TIME, S7UserDataSubfunction.SET_CLOCK, empty=True)

    async def close(self) -> None:
        """Say goodbye (COTP disconnect) and close the socket; errors do not matter here."""
        self._broken = True
        with contextlib.suppress(Exception):
            async with asyncio.timeout(self._timeout):
                await self._connection.disconnect()
