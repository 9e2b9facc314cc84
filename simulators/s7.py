"""A Siemens S7 CPU on loopback: python-snap7's own server, extended where a real CPU differs.

The stock python-snap7 3.3.0 server answers reads with real per-item codes (0x0A, 0x05) and
serves setup, SZL 0x0011 and the clock. Added here, because the tests need a real CPU's ways:
multi-variable writes with a code per item and BOOL written as one bit (the stock server takes
one item and replaces the whole byte), write protection (0x03); the P area (0x80) and S7-200 V
memory as DB1; a clock that keeps the time it is set to; CPU state (SZL 0x0424); SZL 0x001C as a
real list, fragmented when the PDU is small, or no SZL at all (S7-200, LOGO!); the checks of a
CPU (called TSAP, PDU size, item count); counters of requests and connections; a stop that drops
every client at once. The server's threads are python-snap7's; start/stop run in a worker thread.
"""

from __future__ import annotations

import asyncio
from collections import Counter
from collections.abc import Callable
import contextlib
from datetime import datetime, timedelta
import socket
import struct
import threading
import time
from typing import Any

from snap7.datatypes import S7Area, S7WordLen
from snap7.server import Server
from snap7.type import SrvArea
from snap7.util import get_date_time_object, set_dt

_AREAS = {"DB": S7Area.DB, "V": S7Area.DB, "M": S7Area.MK, "I": S7Area.PE, "Q": S7Area.PA}
_AREAS |= {"T": S7Area.TM, "C": S7Area.CT}
_IDENTITY = ("PLC Bridge", "CPU 315-2 PN/DP", "", "Original Siemens Equipment")
_WRONG_FRAMES = 0x8500


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


class _Server(Server):
    """python-snap7's server with the extensions listed in the module docstring."""

    def __init__(self, sim: S7Simulator, max_clients: int) -> None:
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
                client_socket.shutdown(socket.SHUT_RDWR)
            super()._handle_client(client_socket, address)
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
        function = request_data[10] if len(request_data) > 11 and request_data[1] == 1 else None
        refused = {"sequence": int.from_bytes(request_data[4:6], "big")}
        if function == 0xF0:  # setup: the PDU is the smaller of what both sides can do
            reply = bytearray(super()._process_request(request_data, client_address) or b"")
            pdu = min(int.from_bytes(request_data[16:18], "big"), self.sim.pdu_size)
            self.pdu[client_address] = pdu
            reply[-2:] = pdu.to_bytes(2, "big")
            return bytes(reply)
        limit = self.pdu.get(client_address, 240)
        too_many = function in (0x04, 0x05) and request_data[11] > self.sim.max_items
        if len(request_data) > limit or too_many:
            return self._build_error_response(refused, _WRONG_FRAMES)
        if function == 0x05:
            answer: bytes | None = self._write_items(request_data)
        else:
            answer = super()._process_request(request_data, client_address)
        if answer is not None and len(answer) > limit:
            return self._build_error_response(refused, _WRONG_FRAMES)
        return answer

    def _parse_address_specification(self, addr_spec: bytes) -> dict[str, Any]:
        if len(addr_spec) >= 9 and addr_spec[8] == 0x80:  # P area: reads see the inputs
            addr_spec = addr_spec[:8] + bytes([S7Area.PE]) + addr_spec[9:]
        return super()._parse_address_specification(addr_spec)

    def _write_items(self, pdu: bytes) -> bytes:
        """Write every item of a multi-variable write; answer a return code per item."""
        parameter_length, data_length = struct.unpack_from(">HH", pdu, 6)
        parameters = pdu[10 : 10 + parameter_length]
        data = pdu[10 + parameter_length : 10 + parameter_length + data_length]
        count, offset, codes = parameters[1], 0, bytearray()
        for index in range(count):
            spec = parameters[2 + 12 * index : 14 + 12 * index]
            _, _, _, word_length, amount, db, area = struct.unpack_from(">BBBBHHB", spec)
            _, transport, length = struct.unpack_from(">BBH", data, offset)
            size = length if transport in (0x03, 0x07, 0x09) else length // 8
            payload = data[offset + 4 : offset + 4 + size]
            offset += 4 + size + (size % 2 if index < count - 1 else 0)
            where = int.from_bytes(spec[9:12], "big")
            codes.append(self._store((area, db, word_length, amount, where), payload))
        header = struct.pack(">BBHHHHBB", 0x32, 0x03, 0, int.from_bytes(pdu[4:6]), 2, count, 0, 0)
        return header + bytes([0x05, count]) + bytes(codes)

    def _store(self, spec: tuple[int, int, int, int, int], data: bytes) -> int:
        """Store one written item; return its code (0xFF, 0x0A, 0x05, 0x07 or 0x03)."""
        area, db, word_length, amount, where = spec
        if self.sim.write_protected:
            return 0x03  # access denied
        area = S7Area.PA if area == 0x80 else area  # P area: writes reach the outputs
        key = (area, db if area == S7Area.DB else 0)
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
            mode = {"RUN": 0x08, "STOP": 0x04}.get(self.sim.cpu_state, 0x00)
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
        data = bytearray(b"\x00\x20" + bytes(8))  # reserved, century (a CPU answers 0x19..)
        set_dt(data, 2, self.sim.clock)
        return self._build_userdata_success_response(request, params, bytes(data))

    def _handle_set_clock(self, request: dict[str, Any], params: dict[str, Any], _: Any) -> bytes:
        raw = bytearray((request.get("data") or {}).get("data", b""))
        if self.sim.write_protected or len(raw) != 10:
            return self._build_userdata_error_response(request, 0x8104)
        self.sim.clock = get_date_time_object(raw, 2)
        return self._build_userdata_success_response(request, params, b"", null_ack=True)


class S7Simulator:
    """An S7 CPU with memory, clock, state and identity, for tests, the demo and the bench."""

    order_code = "6ES7 315-2EH14-0AB0"
    firmware = (3, 2, 6)
    serial = "S C-X4U421302009"

    def __init__(
        self,
        *,
        rack: int = 0,
        slot: int = 1,
        remote_tsap: int | None = None,
        pdu_size: int = 480,
        max_items: int = 20,
        max_clients: int = 8,
        szl: bool = True,
        dbs: dict[int, int] | None = None,
        area_size: int = 256,
    ) -> None:
        """Prepare the memory; `remote_tsap` (e.g. 0x1001) replaces the rack/slot check."""
        self.rack, self.slot, self.remote_tsap = rack, slot, remote_tsap
        self.pdu_size, self.max_items, self.szl = pdu_size, max_items, szl
        self.host, self.port = "127.0.0.1", 0
        self.requests = 0
        self.calls: Counter[str] = Counter()
        self.connections = 0
        self.cpu_state = "RUN"
        self.write_protected = False
        self.on_request: Callable[[bytes], None] | None = None  # runs in the server's thread
        # SZL 0x001C records by index, in a CPU's order: 1 name, 2 module, 5 serial, 7 type
        self.identity = dict(enumerate(_IDENTITY, 1)) | {5: self.serial, 7: _IDENTITY[1]}
        self.identity |= {8: "MMC 267FF11F", 9: "", 10: "", 11: ""}
        self._clock = (datetime.now().replace(microsecond=0), time.monotonic())
        self._server = _Server(self, max_clients)
        for area in (S7Area.MK, S7Area.PE, S7Area.PA, S7Area.TM, S7Area.CT):
            size = area_size * (2 if area in (S7Area.TM, S7Area.CT) else 1)  # T, C: 2 bytes
            self._server.register_area(SrvArea[area.name], 0, bytearray(size))
        for number, size in (dbs or {1: 1024}).items():
            self.add_db(number, size)

    def accepts(self, called_tsap: bytes | None) -> bool:
        """True when the CPU serves this called TSAP (rack/slot of any connection type)."""
        if called_tsap is None or len(called_tsap) != 2:
            return False
        if self.remote_tsap is not None:
            return int.from_bytes(called_tsap, "big") == self.remote_tsap
        return called_tsap[0] in (1, 2, 3) and called_tsap[1] == self.rack << 5 | self.slot

    def count(self, pdu: bytes) -> None:
        """Count one request by kind (setup, read, write, szl, clock), then call `on_request`."""
        self.requests += 1
        if len(pdu) > 15 and pdu[1] == 0x07:
            self.calls[{0x04: "szl", 0x07: "clock"}.get(pdu[15] & 0x0F, "userdata")] += 1
        elif len(pdu) > 10:
            self.calls[{0xF0: "setup", 0x04: "read", 0x05: "write"}.get(pdu[10], "other")] += 1
        if self.on_request is not None:
            self.on_request(pdu)

    @property
    def clock(self) -> datetime:
        """The CPU clock (naive local time), running from when it was last set."""
        base, since = self._clock
        return base + timedelta(seconds=time.monotonic() - since)

    @clock.setter
    def clock(self, value: datetime) -> None:
        self._clock = (value, time.monotonic())

    def add_db(self, number: int, size: int) -> None:
        """Create DB `number` of `size` bytes (zeros)."""
        self._server.register_area(SrvArea.DB, number, bytearray(size))

    def _memory(self, area: str, db: int) -> tuple[bytearray, threading.Lock, int]:
        """Return an area's bytes, lock and bytes per element (T and C: two)."""
        kind = _AREAS[area.upper()]
        key = (kind, 1 if area.upper() == "V" else db if kind == S7Area.DB else 0)
        unit = 2 if kind in (S7Area.TM, S7Area.CT) else 1
        return self._server.memory_areas[key], self._server.area_locks[key], unit

    def set_bytes(self, area: str, start: int, data: bytes, *, db: int = 0) -> None:
        """Put bytes into DB/V/M/I/Q (start: byte) or T/C (start: number, two bytes each)."""
        memory, lock, unit = self._memory(area, db)
        if start * unit + len(data) > len(memory):
            raise ValueError(f"{area} has {len(memory)} bytes: {len(data)} at {start} do not fit")
        with lock:
            memory[start * unit : start * unit + len(data)] = data

    def get_bytes(self, area: str, start: int, size: int, *, db: int = 0) -> bytes:
        """Return `size` bytes of DB/V/M/I/Q (from a byte) or T/C (from a number)."""
        memory, lock, unit = self._memory(area, db)
        with lock:
            return bytes(memory[start * unit : start * unit + size])

    def set_db(self, number: int, start: int, data: bytes) -> None:
        """Put bytes into a DB."""
        self.set_bytes("DB", start, data, db=number)

    def get_db(self, number: int, start: int, size: int) -> bytes:
        """Return bytes of a DB."""
        return self.get_bytes("DB", start, size, db=number)

    def drop_clients(self) -> None:
        """Cut every client connection now (a pulled cable); the CPU keeps listening."""
        self._server.drop_clients()

    async def start(self, host: str = "127.0.0.1", port: int = 0) -> None:
        """Listen on host:port (0 picks a free port; `port` tells which afterwards)."""
        await asyncio.to_thread(self._server.start_to, host, port)
        assert self._server.server_socket is not None
        self.host, self.port = host, self._server.server_socket.getsockname()[1]

    async def stop(self) -> None:
        """Stop listening, drop every client and wait for the server's threads."""
        await asyncio.to_thread(self._stop)

    def _stop(self) -> None:
        """Blocking part of `stop`."""
        with self._server.client_lock:
            threads = list(self._server.clients)
        self._server.drop_clients()
        self._server.stop()
        self._server.drop_clients()
        for thread in threads:
            thread.join(timeout=2.0)

    async def restart(self) -> None:
        """Stop and start on the same port (a CPU reboot; memory is kept)."""
        await self.stop()
        await self.start(self.host, self.port)
