"""A Siemens S7 CPU on loopback: python-snap7's own server, extended where a real CPU differs.

The server and its extensions are in simulators/s7/server.py; this is the CPU around it:
memory by area, clock, state, identity, counters of requests and connections, and `animate` for
the demo. The server's threads are python-snap7's; start/stop run in a worker thread.
"""

from __future__ import annotations

import asyncio
from collections import Counter
from collections.abc import Callable
from datetime import datetime, timedelta
import math
import struct
import threading
import time

from snap7.datatypes import S7Area
from snap7.type import SrvArea

from .server import CpuServer

_AREAS = {"DB": S7Area.DB, "V": S7Area.DB, "M": S7Area.MK, "I": S7Area.PE, "Q": S7Area.PA}
_AREAS |= {"T": S7Area.TM, "C": S7Area.CT}
_IDENTITY = ("PLC Bridge", "CPU 315-2 PN/DP", "", "Original Siemens Equipment")


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
        max_items: int | None = None,
        max_clients: int = 8,
        szl: bool = True,
        dbs: dict[int, int] | None = None,
        area_size: int = 256,
        family: str = "s7_300_1500",
        has_clock: bool = True,
    ) -> None:
        """Prepare the memory; `remote_tsap` (e.g. 0x1001) replaces the rack/slot check.

        `family` "s7_200" serves timers and counters on the S7-200's area codes (0x1F, 0x1E)
        and refuses the S7-300's (0x1D, 0x1C); `has_clock` False refuses clock requests.
        """
        self.rack, self.slot, self.remote_tsap = rack, slot, remote_tsap
        self.pdu_size, self.max_items, self.szl = pdu_size, max_items, szl
        # A job of more than `max_items` (None: whatever the PDU carries) is refused with the
        # header error `too_many_error` ("refuse"), answered for its first items only
        # ("truncate"), or answered with `too_many_code` past them ("item_codes"): READINGS.md
        self.too_many, self.too_many_error, self.too_many_code = "refuse", 0x8500, 0x0A
        self.family, self.has_clock = family, has_clock
        self.host, self.port = "127.0.0.1", 0
        self.requests = 0
        self.calls: Counter[str] = Counter()
        self.connections = 0
        self.cpu_state: str | int = "RUN"  # RUN, STOP, STARTUP, HOLD, DEFECT, or a raw bzu-id
        self.write_protected = False
        # How the CPU keeps a counter's value in the C area: three BCD digits (STEP 7's
        # definition) or a binary word (what S7.Net's Counter type reads): READINGS.md row 15
        self.counters = "bcd"
        self.put_get_refused = False  # an S7-1200/1500 without "Permit PUT/GET": jobs get 0x8104
        # On the wire (server.Wire; READINGS.md rows 17-19): replies in COTP frames of
        # `frame_size` bytes; connections idle `idle_close` s closed ("fin") or reset at the next
        # request ("reset"); `silent`: requests taken and never answered, nothing closed
        self.frame_size: int | None = None
        self.idle_close: float | None = None
        self.idle_close_how = "fin"
        self.silent = False
        self.on_request: Callable[[bytes], None] | None = None  # runs in the server's thread
        # SZL 0x001C records by index, in a CPU's order: 1 name, 2 module, 5 serial, 7 type
        self.identity = dict(enumerate(_IDENTITY, 1)) | {5: self.serial, 7: _IDENTITY[1]}
        self.identity |= {8: "MMC 267FF11F", 9: "", 10: "", 11: ""}
        self._clock = (datetime.now().replace(microsecond=0), time.monotonic())
        self._server = CpuServer(self, max_clients)
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

    def animate(self, elapsed: float) -> None:
        """Move the demo values (called about once a second, `elapsed` seconds since start).

        DB1.DBD0 (REAL) drifts like a room temperature, MW20 (INT) counts up by one per call;
        the demo boiler's water (DB1.DBW50, tenths of a degree) drifts and raises Overheat (bit
        0 of DB1.DBW70) above its set point (DB1.DBW52); all other memory stays as it is.
        """
        temperature = round(21.0 + 1.5 * math.sin(2 * math.pi * elapsed / 600), 1)
        if (S7Area.DB, 1) in self._server.memory_areas:
            self.set_db(1, 0, struct.pack(">f", temperature))
        if len(self._server.memory_areas.get((S7Area.DB, 1), b"")) >= 72:  # the demo's DB1
            water = round(550 + 50 * math.sin(2 * math.pi * elapsed / 600))
            target, alarms = struct.unpack(">hxxxxxxxxxxxxxxxxh", self.get_db(1, 52, 20))
            alarms = alarms & ~1 | int(0 < target < water)
            self.set_db(1, 50, struct.pack(">h", water))
            self.set_db(1, 70, struct.pack(">h", alarms))
        memory, lock, _ = self._memory("M", 0)
        with lock:
            count = int.from_bytes(memory[20:22], "big", signed=True)
            count = count + 1 if count < 0x7FFF else -0x8000  # wraps as an INT does
            memory[20:22] = count.to_bytes(2, "big", signed=True)

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

    def set_counter(self, number: int, count: int) -> None:
        """Put a count (0..999) into counter C`number` the way `counters` says the CPU keeps it."""
        word = count if self.counters == "binary" else int(str(count), 16)
        self.set_bytes("C", number, word.to_bytes(2, "big"))

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

    def reboot(self, downtime: float = 0.0) -> threading.Event:
        """Reboot from any thread, even inside a request (`on_request`), without waiting.

        Every client is cut at once; the CPU is away for `downtime` seconds, then listens on the
        same port with its memory kept. The event returned is set once it is back.
        """
        back = threading.Event()
        self._server.drop_clients()

        def run() -> None:
            self._stop()
            time.sleep(downtime)
            self._server.start_to(self.host, self.port)
            back.set()

        threading.Thread(target=run, name="s7-reboot", daemon=True).start()
        return back

    async def restart(self) -> None:
        """Stop and start on the same port (a CPU reboot; memory is kept)."""
        await self.stop()
        await self.start(self.host, self.port)
