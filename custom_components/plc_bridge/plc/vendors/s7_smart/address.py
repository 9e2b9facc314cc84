"""S7-200 SMART addresses: parse, check the range, and combine with a data mode."""

from __future__ import annotations

from dataclasses import dataclass, replace
import re

from ...errors import PlcAddressError
from ...shifting import BYTES

MODES = ("signed", "unsigned", "float", "string", "raw")
"""The Web API's data modes (manual 8.2), also the point form's data types."""
MAX_STRING = 254  # an S7-200 SMART string: one length byte, then up to 254 characters
_DECLARED = re.compile(r"string\[([0-9]{1,4})\]")

BOOL = "bool"
DATE = "date"

# The largest memory of the family (CPU ST60/SR60); a smaller CPU answers 3004 per node.
SIZES: dict[str, int] = {"V": 20480, "I": 32, "Q": 32, "M": 32, "SM": 1536, "AIW": 112, "AQW": 112}
COUNTS: dict[str, tuple[int, int]] = {"T": (256, 16), "C": (256, 16), "HC": (6, 32)}
NAMES: dict[str, str] = {
    "V": "V memory",
    "I": "process inputs (I)",
    "Q": "process outputs (Q)",
    "M": "M memory",
    "SM": "special memory (SM)",
    "AIW": "analog inputs (AIW)",
    "AQW": "analog outputs (AQW)",
    "T": "timers (T)",
    "C": "counters (C)",
    "HC": "high-speed counters (HC)",
}
_WIDTHS = {"B": 8, "W": 16, "D": 32}
_PREFIX = {8: "B", 16: "W", 32: "D"}
_N = "[0-9]{1,9}"  # ASCII digits (\d takes any script's), few enough for int() (4,300 at most)
_PATTERN = re.compile(
    rf"(?P<area>SM|V|I|Q|M)(?:(?P<size>[BWD])(?P<index>{_N})|(?P<byte>{_N})\.(?P<bit>{_N}))"
    rf"|(?P<analog>AIW|AQW)(?P<word>{_N})|(?P<counter>HC|T|C)(?P<number>{_N})|(?P<date>DATE)"
)
EXAMPLES = "V10.3, VB100, VW100, VD100, I0.0, QB0, MW4, SMB28, AIW16, T37, C10, HC0 or DATE"


@dataclass(frozen=True, slots=True)
class Address:
    """One parsed address: memory area, byte offset (or T/C/HC number), bit, width in bits."""

    area: str  # V, I, Q, M, SM, AIW, AQW, T, C, HC or DATE
    index: int  # byte offset; the timer, counter or high-speed counter number for T, C, HC
    bit: int | None = None
    width: int = 0  # 1 for a bit, 8/16/32 for bytes, words and double words, 0 for DATE

    @property
    def text(self) -> str:
        """The address as the PLC's documentation spells it (upper case, no leading zeros)."""
        if self.area == "DATE":
            return "DATE"
        if self.bit is not None:
            return f"{self.area}{self.index}.{self.bit}"
        if self.area in COUNTS or self.area in ("AIW", "AQW"):
            return f"{self.area}{self.index}"
        return f"{self.area}{_PREFIX[self.width]}{self.index}"

    @property
    def is_byte_area(self) -> bool:
        """True for V, I, Q, M and SM, the areas addressed by bit, byte, word or double word."""
        return self.area in ("V", "I", "Q", "M", "SM")

    @property
    def room(self) -> int:
        """How many bytes the memory area has from this address on (not for T, C, HC, DATE)."""
        return SIZES[self.area] - self.index


def parse_address(text: str) -> Address:
    """Parse an address case-insensitively; raise PlcAddressError with a message for a form."""
    match = _PATTERN.fullmatch(text.strip().upper())
    if match is None:
        raise PlcAddressError(f"{text!r} is not an S7-200 SMART address; try {EXAMPLES}")
    if match["date"]:
        return Address("DATE", 0)
    if match["area"]:
        area = match["area"]
        if match["size"]:
            address = Address(area, int(match["index"]), None, _WIDTHS[match["size"]])
        else:
            address = Address(area, int(match["byte"]), int(match["bit"]), 1)
            if address.bit is not None and address.bit > 7:
                raise PlcAddressError(
                    f"{text.strip().upper()} names bit {address.bit}; bits are 0..7"
                )
    elif match["analog"]:
        address = Address(match["analog"], int(match["word"]), None, 16)
        if address.index % 2:
            raise PlcAddressError(
                f"{address.text} is not a word address; {NAMES[address.area]} "
                f"are even numbers (0, 2, .. {SIZES[address.area] - 2})"
            )
    else:
        count, width = COUNTS[match["counter"]]
        address = Address(match["counter"], int(match["number"]), None, width)
        if address.index >= count:
            raise PlcAddressError(
                f"{address.text} is outside {NAMES[address.area]} (0..{count - 1})"
            )
        return address
    _check_range(address)
    return address


def _check_range(address: Address) -> None:
    """Refuse an address that starts or ends outside its memory area."""
    size = SIZES[address.area]
    last = size - 2 if address.area in ("AIW", "AQW") else size - 1
    if address.index > last:
        raise PlcAddressError(f"{address.text} is outside {NAMES[address.area]} (0..{last})")
    if address.room < max(1, address.width // 8):
        raise PlcAddressError(
            f"{address.text} runs past the end of {NAMES[address.area]} (0..{last}); "
            f"it needs {address.width // 8} bytes"
        )


def covered(address: Address, kind: str, length: int | None = None) -> tuple[str, int, int]:
    """Return the area and the [start, end) a point covers: its bytes, or a T, C, HC number.

    A bit covers its byte; a string its length byte and `length` characters: those declared
    (`string[20]`) or read, else as many as any string may hold (254), as long as the area
    lasts.
    """
    if not address.is_byte_area and address.area not in ("AIW", "AQW"):
        return address.area, address.index, address.index + 1
    if kind == "string":
        size = 1 + (MAX_STRING if length is None else length)
    else:
        size = max(1, address.width // 8)
    return address.area, address.index, min(address.index + size, SIZES[address.area])


def parse_mode(data_type: str) -> tuple[str, int | None]:
    """Return a data type's mode and declared string length (`string[20]`: "string", 20).

    The CPU keeps no string's size (a length byte, then the characters the program wrote);
    a declared length is the user's word for the room the program keeps for it.
    """
    mode = re.sub(r"\s+", "", data_type).lower()
    if (declared := _DECLARED.fullmatch(mode)) is None:
        return mode, None
    length = int(declared[1])
    if not 1 <= length <= MAX_STRING:
        raise PlcAddressError(f"a string holds 1..{MAX_STRING} characters, not {length}")
    return "string", length


def check_declared(address: Address, length: int | None) -> None:
    """Refuse a declared string length that runs past the end of the address's area."""
    if length is not None and address.room < 1 + length:
        raise PlcAddressError(
            f"{address.text} cannot hold a string of {length} characters: "
            f"{NAMES[address.area]} ends {address.room - 1} bytes after its length byte"
        )


READ_ONLY_SM = ((0, 30), (1000, 1536))
"""SMB0..SMB29 (system status) and SMB1000..SMB1535 (module information) are read-only."""
INPUTS = ("I", "AIW", "HC")
"""Process inputs, analog inputs and high-speed counters: the CPU writes them, never a client."""


def writable(address: Address, kind: str) -> bool:
    """False where no write can ever reach the address: inputs and read-only SM bytes."""
    if address.area in INPUTS:
        return False
    if address.area == "SM":
        _, start, end = covered(address, kind)
        return not any(start < high and low < end for low, high in READ_ONLY_SM)
    return True


def point_kind(address: Address, mode: str) -> str:
    """Return how a point is read and written: bool, date, or the checked data mode.

    A bit is a BOOL and DATE is the clock whatever mode the point names (the device ignores it).
    """
    mode = mode.strip().lower()
    if mode not in MODES:
        raise PlcAddressError(
            f"unknown data type {mode!r}; use one of {', '.join(MODES)} or string[n]"
        )
    if address.area == "DATE":
        return DATE
    if address.bit is not None:
        return BOOL
    if mode == "float" and (address.width != 32 or not address.is_byte_area):
        raise PlcAddressError(
            f"{address.text} cannot hold a float; a REAL needs a double word (VD, ID, QD, MD, SMD)"
        )
    if mode == "string" and (address.width != 8 or not address.is_byte_area):
        raise PlcAddressError(
            f"{address.text} cannot hold a string; strings start at a byte (VB, IB, QB, MB, SMB)"
        )
    return mode


def shift(text: str, by: int, unit: str) -> str:
    """Return an address moved by `by` bytes (VB100 + 20 = VB120, V10.3 + 2 = V12.3).

    Analog words move by an even count; timers, counters and high-speed counters (numbered,
    not addressed by byte) and the clock (DATE, one per PLC) do not move. The moved address
    is checked as typed (within its area). Raise PlcAddressError.
    """
    address = parse_address(text)
    if unit != BYTES:
        raise PlcAddressError(f"{address.text}: an S7-200 SMART address moves by bytes")
    if address.area == "DATE":
        raise PlcAddressError("DATE is the PLC's clock: it has no place to move to")
    if address.area in COUNTS:
        raise PlcAddressError(f"{address.text} is numbered, not addressed by byte")
    if address.area in ("AIW", "AQW") and by % 2:
        raise PlcAddressError(f"{address.text} is an analog word: move it by an even count")
    if address.index + by < 0:
        raise PlcAddressError(f"{address.text} + {by} bytes falls below byte 0")
    return parse_address(replace(address, index=address.index + by).text).text
