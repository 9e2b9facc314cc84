"""The CPU side of the simulator: data areas and clock, addressed as the Web API does."""

from __future__ import annotations

from datetime import datetime
import math
import re
import struct
from typing import Any, NamedTuple

from .errors import INVALID_ADDRESS, INVALID_MODE, INVALID_VALUE, Fault

type Value = bool | int | float | str | datetime | list[int]

DATE_FORMAT = "%Y-%m-%d %H:%M:%S"
SIZES = {"V": 20480, "I": 32, "Q": 32, "M": 32, "SM": 1536, "AIW": 112, "AQW": 112}
SIZES |= {"T": 512, "C": 512, "HC": 24}  # 256 timers and counters of 16 bits, 6 HC of 32 bits
READ_ONLY_SM = 30  # SMB0..SMB29 hold system status bits the user program cannot write
MODES = ("signed", "unsigned", "float", "string", "raw")
_ADDRESS = re.compile(
    r"(?P<area>SM|V|I|Q|M)(?:(?P<size>[BWD])(?P<index>\d+)|(?P<byte>\d+)\.(?P<bit>\d+))"
    r"|(?P<analog>AIW|AQW)(?P<word>\d+)|(?P<counter>HC|T|C)(?P<number>\d+)|(?P<date>DATE)"
)
_WIDTHS = {"B": 8, "W": 16, "D": 32}
_COUNTERS = {"T": (256, 16), "C": (256, 16), "HC": (6, 32)}


class Where(NamedTuple):
    """A located address: memory area, byte offset, bit, width in bits, and the data mode."""

    area: str
    offset: int
    bit: int | None
    width: int
    mode: str


def _single(value: float) -> float:
    """Return the shortest decimal that reads back as the same REAL (like the PLC prints it)."""
    stored = struct.unpack(">f", struct.pack(">f", value))[0]
    for digits in range(1, 10):
        text = float(f"{stored:.{digits}g}")
        if struct.pack(">f", text) == struct.pack(">f", stored):
            return text
    return float(stored)  # pragma: no cover - 9 significant digits always round-trip


REAL_FORMATS = ("shortest", "double", "fixed")
"""How a firmware prints a REAL (READINGS.md row 18): the shortest decimal of the float32
(22.3), its double expansion (22.299999237060547), or printf's six decimals (22.299999)."""


def printed_real(value: float, real_format: str) -> float:
    """Return a REAL (given as its shortest decimal) as a firmware with `real_format` prints it."""
    double = struct.unpack(">f", struct.pack(">f", value))[0]
    return double if real_format == "double" else float(f"{double:.6f}")


class Memory:
    """The data areas (V sized as in an ST60/SR60) and the real-time clock of one CPU."""

    def __init__(self) -> None:
        self.areas = {area: bytearray(size) for area, size in SIZES.items()}
        self.v_size = SIZES["V"]
        self.clock = datetime.now().replace(microsecond=0)

    def locate(self, var: str, mode: Any) -> Where:
        """Return (area, byte offset, bit, width in bits, mode) of an address, case-insensitive."""
        if not isinstance(mode, str) or mode.lower() not in MODES:
            raise Fault(INVALID_MODE)
        mode = mode.lower()
        match = _ADDRESS.fullmatch(var.strip().upper())
        if match is None:
            raise Fault(INVALID_ADDRESS)
        if match["date"]:
            return Where("DATE", 0, None, 0, mode)
        bit: int | None = None
        if match["area"]:
            area = match["area"]
            if match["size"]:
                offset, width = int(match["index"]), _WIDTHS[match["size"]]
            else:
                offset, bit, width = int(match["byte"]), int(match["bit"]), 1
                if bit > 7:
                    raise Fault(INVALID_ADDRESS)
        elif match["analog"]:
            area, offset, width = match["analog"], int(match["word"]), 16
            if offset % 2:
                raise Fault(INVALID_ADDRESS)
        else:
            area, number = match["counter"], int(match["number"])
            count, width = _COUNTERS[area]
            if number >= count:
                raise Fault(INVALID_ADDRESS)
            offset = number * width // 8
        size = self.v_size if area == "V" else SIZES[area]
        if offset + max(1, width // 8) > min(size, len(self.areas[area])):
            raise Fault(INVALID_ADDRESS)
        if width > 1 and (
            (mode == "float" and (width != 32 or area == "HC"))
            or (mode == "string" and (width != 8 or not match["area"]))
        ):
            raise Fault(INVALID_MODE)
        return Where(area, offset, bit, width, mode)

    def load(self, where: Where) -> Any:
        """Return the wire value of a located address."""
        area, offset, bit, width, mode = where
        if area == "DATE":
            return self.clock.strftime(DATE_FORMAT)
        memory = self.areas[area]
        if bit is not None:
            return (memory[offset] >> bit) & 1
        data = bytes(memory[offset : offset + width // 8])
        if mode == "string":
            length = min(memory[offset], 254)
            return memory[offset + 1 : offset + 1 + length].decode("latin-1")
        if mode == "raw":
            return list(data)
        if mode == "float":
            return _single(struct.unpack(">f", data)[0])
        return int.from_bytes(data, "big", signed=mode == "signed")

    def put_string(self, offset: int, data: bytes) -> None:
        """Put a string into V memory as the user program does: a length byte, then any bytes."""
        if len(data) > 254 or offset + 1 + len(data) > self.v_size:
            raise ValueError(f"{len(data)} bytes do not fit a string at VB{offset}")
        self.areas["V"][offset : offset + 1 + len(data)] = bytes([len(data)]) + data

    def store(self, where: Where, value: Any) -> None:
        """Encode a wire value into memory; refuse what does not fit (INVALID_VALUE)."""
        area, offset, bit, width, mode = where
        if area == "DATE":
            try:
                when = datetime.strptime(value, DATE_FORMAT)
            except (TypeError, ValueError):
                raise Fault(INVALID_VALUE) from None
            if not 2000 <= when.year <= 2099:  # the RTC keeps a two-digit year
                raise Fault(INVALID_VALUE)
            self.clock = when
            return
        memory = self.areas[area]
        if bit is not None:
            if value not in (0, 1) or isinstance(value, float):
                raise Fault(INVALID_VALUE)
            memory[offset] = (memory[offset] & ~(1 << bit)) | (int(value) << bit)
            return
        size = self.v_size if area == "V" else SIZES[area]
        data = _encode(mode, width // 8, size - offset - 1, value)
        memory[offset : offset + len(data)] = data


def _encode(mode: str, length: int, room: int, value: Any) -> bytes:
    """Return the bytes of a value in a mode (room: characters a string may still take)."""
    if mode == "string":
        if not isinstance(value, str) or not value.isascii() or len(value) > min(room, 254):
            raise Fault(INVALID_VALUE)
        return bytes([len(value)]) + value.encode("ascii")
    if mode == "raw":
        if not isinstance(value, list) or len(value) != length:
            raise Fault(INVALID_VALUE)
        if not all(isinstance(b, int) and not isinstance(b, bool) for b in value):
            raise Fault(INVALID_VALUE)
        try:
            return bytes(value)
        except ValueError:
            raise Fault(INVALID_VALUE) from None
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise Fault(INVALID_VALUE)
    try:
        if mode == "float":
            if not math.isfinite(value):
                raise Fault(INVALID_VALUE)
            return struct.pack(">f", value)
        if isinstance(value, float):
            raise Fault(INVALID_VALUE)
        return value.to_bytes(length, "big", signed=mode == "signed")
    except (OverflowError, struct.error):
        raise Fault(INVALID_VALUE) from None
