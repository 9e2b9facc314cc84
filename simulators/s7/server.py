"""python-snap7's S7 server, extended where a real CPU differs (used by simulators/s7/cpu.py).

The stock python-snap7 3.3.0 server answers reads with real per-item codes (0x0A, 0x05) and
serves setup, SZL 0x0011 and the clock. Added here: multi-variable writes with a code per item
and BOOL written as one bit (the stock server takes one item and replaces the whole byte), write
protection (0x03); the P area (0x80: reads see the inputs, writes reach the outputs); S7-200
timers and counters on area codes 0x1F/0x1E (the stock server's area enum has neither); a clock
that keeps the time it is set to, or none at all; every CPU state of SZL 0x0424; SZL 0x001C as a
real list, fragmented when the PDU is small, or no SZL at all (S7-200, LOGO!); the checks of a
CPU (called TSAP, PDU size, item count); a stop that drops every client at once. On the wire
(`Wire`): replies split into COTP frames of a few bytes, idle connections closed as a CPU, CP or
firewall closes them, and a CPU that stops answering without closing (READINGS.md, rows 17-19).
"""

from __future__ import annotations

import contextlib
import select
import socket
import struct
import threading
import time
from typing import TYPE_CHECKING, Any

from snap7.datatypes import S7Area, S7WordLen
from snap7.server import Server
from snap7.util import get_date_time_object, set_dt

if TYPE_CHECKING:
    from .cpu import S7Simulator

_WRONG_FRAMES = 0x8500
_NOT_AVAILABLE = 0x8104
_NO_DB = 0xFFFF  # a DB number no area is registered under: its items answer 0x0A
# An S7-200 (CP 243-1) serves timers on 0x1F and counters on 0x1E, as word length and area.
_S7_200 = {0x1F: S7Area.TM, 0x1E: S7Area.CT}
# SZL 0x0424 bzu-id: the mode now in bits 0..3 (a CPU may put the mode before in bits 4..7)
_STATES = {"RUN": 0x08, "STOP": 0x04, "STARTUP": 0x05, "HOLD": 0x0A, "DEFECT": 0x0D}
_KNOWN_AREAS = frozenset(S7Area)


def _peek_called_tsap(sock: socket.socket) -> bytes | None:
    """Return the called TSAP of the COTP connection request waiting on a socket (unread)."""
    deadline, data = time.monotonic() + 1.0, b""
    while time.monotonic() < deadline and (len(data) < 4 or len(data) < int.from_bytes(data[2:4])):
        with contextlib.suppress(OSError):
            data = sock.recv(256, socket.MSG_PEEK)
        time.sleep(0.005 if len(data) < 4 else 0)
    offset = 4 + 7  # TPKT, then the fixed part of the CR
    while offset + 2 <= len(data) and data[offset] != 0xC2:
        offset += 2 + data[offset + 1]
    return data[offset + 2 : offset + 2 + data[offset + 1]] if offset + 2 <= len(data) else None


class Wire:
    """A client's socket as the CPU uses it: replies in frames, idle connections closed.

    `frame_size` splits every reply into COTP data frames of that many bytes, the last marked
    EOT. `idle_close` closes a connection idle that many seconds (0: after each reply):
    `idle_close_how` "fin" closes it then, as a CPU or CP does; "reset" lets it be and resets it
    when the next request comes, as a firewall that forgot the connection does.
    """

    def __init__(self, sock: socket.socket, sim: S7Simulator) -> None:
        """Wrap an accepted socket."""
        self._sock, self._sim = sock, sim
        self._idle_since: float | None = time.monotonic()  # None while a request comes in

    def __getattr__(self, name: str) -> Any:
        """Everything else is the socket's."""
        return getattr(self._sock, name)

    def recv(self, size: int, *flags: int) -> bytes:
        """Receive; an idle connection past `idle_close` is closed instead (returns EOF)."""
        idle, since = self._sim.idle_close, self._idle_since
        if idle is None or since is None or flags:
            return self._sock.recv(size, *flags)
        if self._sim.idle_close_how == "fin":
            wait, timeout = since + idle - time.monotonic(), self._sock.gettimeout()
            early = timeout is None or wait < timeout  # else the socket's timeout comes first
            if early and not select.select([self._sock], [], [], max(wait, 0.0))[0]:
                self._sock.shutdown(socket.SHUT_RDWR)
                return b""
        data = self._sock.recv(size)
        if data and self._sim.idle_close_how == "reset" and time.monotonic() - since > idle:
            self._sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
            return b""  # the handler closes the socket: a reset, the request unanswered
        if data:
            self._idle_since = None
        return data

    def sendall(self, data: bytes) -> None:
        """Send a frame; a reply (a COTP data frame) in frames of `frame_size` bytes."""
        size = self._sim.frame_size
        if size and len(data) > 7 and data[5] == 0xF0:
            body = data[7:]
            chunks = [body[at : at + size] for at in range(0, len(body), size)] or [b""]
            for index, chunk in enumerate(chunks):
                eot = 0x80 if index == len(chunks) - 1 else 0x00
                head = struct.pack(">BBHBBB", 3, 0, len(chunk) + 7, 2, 0xF0, eot)
                self._sock.sendall(head + chunk)
        else:
            self._sock.sendall(data)
        if len(data) > 5 and data[5] == 0xF0:  # a reply; the connection confirm starts no idling
            self._idle_since = time.monotonic()


class CpuServer(Server):
    """python-snap7's server with the extensions listed in the module docstring."""

    def __init__(self, sim: S7Simulator, max_clients: int) -> None:
        """Serve the simulator's memory, state and identity to at most `max_clients`."""
        super().__init__(log=False, max_clients=max_clients)
        self.sim = sim
        self.sockets: set[socket.socket] = set()
        self.pdu: dict[tuple[str, int], int] = {}
        self.pending: dict[tuple[tuple[str, int], int], bytes] = {}
        self.guard = threading.Lock()

    def _handle_client(self, client_socket: socket.socket, address: tuple[str, int]) -> None:
        with self.guard:
            self.sockets.add(client_socket)
        try:
            if self.sim.accepts(_peek_called_tsap(client_socket)):
                self.sim.connections += 1
            else:  # a CPU refuses a rack/slot or TSAP it does not have
                with contextlib.suppress(OSError):  # a client that is gone already
                    client_socket.shutdown(socket.SHUT_RDWR)
            super()._handle_client(Wire(client_socket, self.sim), address)  # type: ignore[arg-type]
        finally:
            with self.guard:
                self.sockets.discard(client_socket)
            self.pdu.pop(address, None)

    def drop_clients(self) -> None:
        """Cut every client connection (a reboot or a pulled cable)."""
        with self.guard:
            for sock in self.sockets:
                with contextlib.suppress(OSError):
                    sock.shutdown(socket.SHUT_RDWR)

    def _process_request(self, request_data: bytes, client_address: tuple[str, int]) -> Any:
        self.sim.count(request_data)
        if self.sim.silent:
            return None
        function = request_data[10] if len(request_data) > 11 and request_data[1] == 1 else None
        refused = {"sequence": int.from_bytes(request_data[4:6], "big")}
        if function == 0xF0:  # setup: the PDU is the smaller of what both sides can do
            reply = bytearray(super()._process_request(request_data, client_address) or b"")
            pdu = min(int.from_bytes(request_data[16:18], "big"), self.sim.pdu_size)
            self.pdu[client_address] = pdu
            reply[-2:] = pdu.to_bytes(2, "big")
            return bytes(reply)
        limit = self.pdu.get(client_address, 240)
        if len(request_data) > limit:
            return self._build_error_response(refused, _WRONG_FRAMES)
        if function in (0x04, 0x05) and self.sim.put_get_refused:
            return self._build_error_response(refused, _NOT_AVAILABLE)
        cap = self.sim.max_items
        over = function in (0x04, 0x05) and cap is not None and request_data[11] > cap
        if over and self.sim.too_many == "refuse":
            return self._build_error_response(refused, self.sim.too_many_error)
        if function == 0x05:
            answer: bytes | None = self._write_items(request_data, cap if over else None)
        elif over and cap is not None:
            answer = self._read_first(request_data, cap, client_address)
        else:
            answer = super()._process_request(request_data, client_address)
        if answer is not None and len(answer) > limit:
            return self._build_error_response(refused, _WRONG_FRAMES)
        return answer

    def _parse_address_specification(self, addr_spec: bytes) -> dict[str, Any]:
        """Parse an address spec after mapping its area as this CPU does (P, S7-200 T/C)."""
        if len(addr_spec) >= 12:
            area, db = self._area(addr_spec[8], int.from_bytes(addr_spec[6:8]))
            word_length = area if area in (S7Area.TM, S7Area.CT) else addr_spec[3]
            head, count, where = addr_spec[:3], addr_spec[4:6], addr_spec[9:12]
            addr_spec = head + bytes([word_length]) + count + db.to_bytes(2) + bytes([area]) + where
        return super()._parse_address_specification(addr_spec)

    def _area(self, code: int, db: int) -> tuple[int, int]:
        """Return the stored area and DB of an item's area code, as this CPU maps them."""
        if code == 0x80:  # P area: reads see the inputs (writes map it to the outputs)
            return S7Area.PE, db
        if self.sim.family == "s7_200":
            if code in _S7_200:
                return _S7_200[code], 0
            if code in (S7Area.TM, S7Area.CT):
                return code, _NO_DB  # an S7-200 has no S7-300 timers and counters
        return (code, db) if code in _KNOWN_AREAS else (S7Area.DB, _NO_DB)

    def _read_first(self, pdu: bytes, cap: int, client: tuple[str, int]) -> bytes | None:
        """Read the first `cap` items only: answer them, or all with `too_many_code` past them.

        "truncate" answers `cap` items, as Snap7's C server does at 20; "item_codes" all asked.
        """
        asked = pdu[11]
        head = struct.pack(">BBHHHH", 0x32, 1, 0, int.from_bytes(pdu[4:6]), 2 + 12 * cap, 0)
        answer = super()._process_request(
            head + bytes([0x04, cap]) + pdu[12 : 12 + 12 * cap], client
        )
        if self.sim.too_many == "truncate" or answer is None or len(answer) < 14:
            return answer
        data, offset, size = bytearray(answer[14:]), 0, 0
        for _ in range(cap):  # find the last item, which now needs its fill byte
            code, transport, length = struct.unpack_from(">BBH", data, offset)
            size = (
                (length if transport in (0x03, 0x07, 0x09) else length // 8) if code == 0xFF else 0
            )
            offset += 4 + size + (size % 2)
        data = data[: offset - size % 2] + bytes(size % 2)
        data += bytes([self.sim.too_many_code, 0, 0, 0]) * (asked - cap)
        header = bytearray(answer[:12])
        header[8:10] = len(data).to_bytes(2, "big")
        return bytes(header) + bytes([0x04, asked]) + bytes(data)

    def _write_items(self, pdu: bytes, cap: int | None = None) -> bytes:
        """Write the items of a multi-variable write (the first `cap`); a return code per item.

        Past `cap`: no code ("truncate") or the code `too_many_code` ("item_codes").
        """
        parameter_length, data_length = struct.unpack_from(">HH", pdu, 6)
        parameters = pdu[10 : 10 + parameter_length]
        data = pdu[10 + parameter_length : 10 + parameter_length + data_length]
        count, offset, codes = parameters[1], 0, bytearray()
        for index in range(count):
            if cap is not None and index >= cap:
                if self.sim.too_many == "item_codes":
                    codes.append(self.sim.too_many_code)
                continue
            spec = parameters[2 + 12 * index : 14 + 12 * index]
            _, _, _, word_length, amount, db, area = struct.unpack_from(">BBBBHHB", spec)
            _, transport, length = struct.unpack_from(">BBH", data, offset)
            size = length if transport in (0x03, 0x07, 0x09) else length // 8
            payload = data[offset + 4 : offset + 4 + size]
            offset += 4 + size + (size % 2 if index < count - 1 else 0)
            where = int.from_bytes(spec[9:12], "big")
            codes.append(self._store((area, db, word_length, amount, where), payload))
        header = struct.pack(">BBHHHHBB", 0x32, 3, 0, int.from_bytes(pdu[4:6]), 2, len(codes), 0, 0)
        return header + bytes([0x05, len(codes)]) + bytes(codes)

    def _store(self, spec: tuple[int, int, int, int, int], data: bytes) -> int:
        """Store one written item; return its code (0xFF, 0x0A, 0x05, 0x07 or 0x03)."""
        area, db, word_length, amount, where = spec
        if self.sim.write_protected:
            return 0x03  # access denied
        area, db = (S7Area.PA, db) if area == 0x80 else self._area(area, db)  # PQ: the outputs
        word_length = area if area in (S7Area.TM, S7Area.CT) else word_length
        key = (area, db if area == S7Area.DB or db == _NO_DB else 0)
        if key not in self.memory_areas:
            return 0x0A
        if word_length == S7WordLen.BIT:
            start, bit, size = where // 8, where % 8, 1
        elif word_length in (S7WordLen.TIMER, S7WordLen.COUNTER):
            start, bit, size = where * 2, None, amount * 2
        else:
            start, bit, size = where // 8, None, amount
        memory = self.memory_areas[key]
        if len(data) != size or start + size > len(memory):
            return 0x07 if len(data) != size else 0x05
        with self.area_locks[key]:
            if bit is None:
                memory[start : start + size] = data
            elif data[0] & 1:
                memory[start] |= 1 << bit
            else:
                memory[start] &= ~(1 << bit) & 0xFF
        return 0xFF

    def _get_szl_data(self, szl_id: int, szl_index: int) -> bytes | None:
        if not self.sim.szl:
            return None
        if szl_id == 0x0424:
            state = self.sim.cpu_state
            mode = state if isinstance(state, int) else _STATES.get(state, 0x00)
            return struct.pack(">HHHBB", 20, 1, 0x4302, 0xFF, mode) + bytes(16)
        if szl_id == 0x001C:
            return struct.pack(">HH", 34, len(self.sim.identity)) + b"".join(
                index.to_bytes(2, "big") + text.encode().ljust(32, b"\x00")
                for index, text in self.sim.identity.items()
            )
        if szl_id == 0x0011:  # records 0x0001 (order code) and 0x0007 (firmware), 28 bytes
            code = self.sim.order_code.encode().ljust(20, b" ")
            firmware = b"\x00\x07" + b" " * 20 + bytes([0, 0, ord("V"), *self.sim.firmware])
            return struct.pack(">HH", 28, 2) + b"\x00\x01" + code + bytes(6) + firmware
        return super()._get_szl_data(szl_id, szl_index)

    def _handle_szl(
        self, request: dict[str, Any], userdata_params: dict[str, Any], client_address: Any
    ) -> bytes:
        """Answer SZL reads, in fragments when the list does not fit the PDU (like a CPU)."""
        key = (client_address, userdata_params.get("sequence", 0))
        rest: bytes
        if userdata_params.get("method") == 0x12 and key in self.pending:
            rest = self.pending.pop(key)
        else:
            reply = super()._handle_szl(request, userdata_params, client_address)
            if len(reply) <= self.pdu.get(client_address, 240):
                return reply
            rest = reply[26:]  # the SZL ID, index, list header and records
        room = self.pdu.get(client_address, 240) - 26  # USERDATA header, parameters, data head
        part, rest = rest[:room], rest[room:]
        reference = 1 + len(self.pending) % 250
        answer = bytearray(self._build_userdata_success_response(request, userdata_params, part))
        if rest:
            self.pending[(client_address, reference)] = rest
            answer[17], answer[19] = reference, 0x01  # data unit reference, "more follows"
        return bytes(answer)

    def _handle_get_clock(self, request: dict[str, Any], params: dict[str, Any], _: Any) -> bytes:
        if not self.sim.has_clock:
            return self._build_userdata_error_response(request, _NOT_AVAILABLE)
        data = bytearray(b"\x00\x20" + bytes(8))  # reserved, century (a CPU answers 0x19..)
        set_dt(data, 2, self.sim.clock)
        return self._build_userdata_success_response(request, params, bytes(data))

    def _handle_set_clock(self, request: dict[str, Any], params: dict[str, Any], _: Any) -> bytes:
        raw = bytearray((request.get("data") or {}).get("data", b""))
        if self.sim.write_protected or len(raw) != 10:
            return self._build_userdata_error_response(request, _NOT_AVAILABLE)
        self.sim.clock = get_date_time_object(raw, 2)
        return self._build_userdata_success_response(request, params, b"", null_ack=True)
