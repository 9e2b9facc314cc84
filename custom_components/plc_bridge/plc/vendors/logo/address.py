"""LOGO! addresses as LOGO!Soft Comfort names them, mapped to the VM area (DB1) per generation.

A LOGO! serves one data block over S7comm, DB1: its variable memory (VM). Bytes 0..849 are
the VM a program's blocks use by parameter (V10.3, VW12); above them the LOGO! keeps images of
its blocks (inputs, outputs, flags, analog values, network I/O), at offsets that differ per
generation. Each address resolves to an S7 `Variable` of DB1, so the S7 planner, codec and link
read and write it unchanged.

Sources of the VM tables (the Siemens LOGO! manuals' "VM mapping" tables, as public projects
quote them; no source found disagrees on an offset):
- 0BA7: openHAB's plclogo binding (`PLCLogoBindingConstants`, LOGO_MEMORY_0BA7) and
  SmartHome.py's logo plugin (`tableVM_IO`): I 923, AI 926, Q 942, AQ 944, M 948, AM 952.
- 0BA8 and later LOGO! 8: openHAB's plclogo binding (LOGO_MEMORY_0BA8): I 1024, AI 1032,
  Q 1064, AQ 1072, M 1104, AM 1118, NI 1246, NAI 1262, NQ 1390, NAQ 1406.
Block counts (how many of each a LOGO! has, often fewer than its image holds): the LOGO!Soft
Comfort help on flags (0BA7: M1..M27, AM1..AM16; 0BA8: M1..M64, AM1..AM64), the LOGO! manual
A5E03556174-01 (0BA7: AQ1, AQ2) and SmartHome.py's plugin README (0BA7: Q16; 0BA8: Q20, AQ8,
NI64, NAI32, NQ64, NAQ16). Where they disagree, simulators/logo/READINGS.md lists the readings.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import lru_cache
import re

from ...errors import PlcAddressError
from ...shifting import BLOCKS, BYTES
from ...types import Point
from ..s7.address import AREA_DB, Variable, normalize_type, variable as s7_variable

VM_DB = 1
VM_USER = 850
"""Bytes of VM a program's parameters use (V0..V849); sources disagree on V850 (READINGS row 3)."""

GENERATIONS: tuple[str, ...] = ("0ba7", "0ba8", "8_x")
"""0BA7; the first LOGO! 8 (…-0BA8); LOGO! 8.FS4 and later (8.1 to 8.4)."""

MODELS = {"0ba7": "LOGO! 0BA7", "0ba8": "LOGO! 8 (0BA8)", "8_x": "LOGO! 8.x"}

DATA_TYPES: tuple[str, ...] = (
    "BOOL",
    "BYTE",
    "WORD",
    "INT",
    "UINT",
    "DWORD",
    "DINT",
    "UDINT",
    "REAL",
)
"""What a LOGO! address holds: a bit, or VM bytes, words and double words; blocks take fewer."""

ANALOG_TYPES = ("INT", "WORD")  # a LOGO! analog value is a signed word; WORD gives it raw


@dataclass(frozen=True, slots=True)
class Block:
    """A kind of LOGO! block: where its image starts in VM, how many there are, word or bit."""

    start: int  # VM byte of block 1
    count: int
    analog: bool
    what: str  # as a message names it


_WHAT = {
    "I": "digital input",
    "Q": "digital output",
    "M": "digital flag",
    "AI": "analog input",
    "AQ": "analog output",
    "AM": "analog flag",
    "NI": "network input",
    "NAI": "network analog input",
    "NQ": "network output",
    "NAQ": "network analog output",
}


def _blocks(table: dict[str, tuple[int, int]]) -> dict[str, Block]:
    """Return a generation's blocks from name: (first VM byte, count)."""
    return {
        name: Block(start, count, name.startswith(("A", "NA")), _WHAT[name])
        for name, (start, count) in table.items()
    }


_LOGO_8 = _blocks(
    {
        "I": (1024, 24),
        "AI": (1032, 8),
        "Q": (1064, 20),
        "AQ": (1072, 8),
        "M": (1104, 64),
        "AM": (1118, 64),
        "NI": (1246, 64),
        "NAI": (1262, 32),
        "NQ": (1390, 64),
        "NAQ": (1406, 16),
    }
)
MAPS: dict[str, dict[str, Block]] = {
    "0ba7": _blocks(
        {"I": (923, 24), "AI": (926, 8), "Q": (942, 16), "AQ": (944, 2), "M": (948, 27)}
        | {"AM": (952, 16)}
    ),
    "0ba8": _LOGO_8,
    "8_x": _LOGO_8,  # no public source shows another map for 8.FS4 or 8.1..8.4
}

WRITABLE = ("V", "NI", "NAI")
"""What a client may write: VM, and the network inputs a partner sends (READINGS row 4)."""

_REFUSED = {
    "I": "the LOGO! reads its inputs from its terminals every cycle",
    "AI": "the LOGO! reads its inputs from its terminals every cycle",
    "Q": "the LOGO! program sets its outputs every cycle",
    "AQ": "the LOGO! program sets its outputs every cycle",
    "M": "the LOGO! program sets its flags every cycle",
    "AM": "the LOGO! program sets its flags every cycle",
    "NQ": "the LOGO! program sets its network outputs every cycle",
    "NAQ": "the LOGO! program sets its network outputs every cycle",
}

_N = "[0-9]{1,5}"
_PATTERN = re.compile(
    rf"(?P<block>NAI|NAQ|NI|NQ|AI|AQ|AM|I|Q|M)(?P<number>{_N})"
    rf"|V(?P<width>[BWD]?)(?P<offset>{_N})(?:\.(?P<bit>{_N}))?"
)
EXAMPLES = "I1, Q1, M1, AI1, AQ1, AM1, NI1, NAI1, V100.3, VB100, VW100 or VD100"


@dataclass(frozen=True, slots=True)
class LogoAddress:
    """An address in LOGO! terms: a block (name, number) or VM (offset, width, bit)."""

    block: str  # I, Q, ..., or V
    number: int  # block number, or VM byte
    width: str = ""  # V only: B, W, D or "" for a bit
    bit: int | None = None

    @property
    def text(self) -> str:
        """The address as LOGO!Soft Comfort writes it (V100.3, VW100, AI1)."""
        if self.block != "V":
            return f"{self.block}{self.number}"
        return f"V{self.number}.{self.bit}" if self.width == "" else f"V{self.width}{self.number}"

    @property
    def writable(self) -> bool:
        """True where a client may write (VM and network inputs)."""
        return self.block in WRITABLE


@lru_cache(maxsize=4096)
def parse(point: Point) -> LogoAddress:
    """Parse a LOGO! address and check its type, valid in some generation; raise PlcAddressError."""
    text = re.sub(r"\s+", "", point.address).upper()
    data_type = normalize_type(point.data_type)
    if data_type not in DATA_TYPES:
        raise PlcAddressError(f"a LOGO! holds no {data_type}; use {', '.join(DATA_TYPES)}")
    match = _PATTERN.fullmatch(text)
    if match is None:
        raise PlcAddressError(f"{point.address!r} is not a LOGO! address; try {EXAMPLES}")
    if match["block"]:
        return _block(match["block"], int(match["number"]), data_type)
    offset, width, bit = int(match["offset"]), match["width"], match["bit"]
    if width == "" and bit is None:
        width = "B"  # python-snap7's Logo and LOGO!Soft's "V 10" read a byte
    if bit is not None and width:
        raise PlcAddressError(f"{point.address!r}: V{width} takes no bit number; try V{offset}.0")
    found = LogoAddress("V", offset, width, None if bit is None else int(bit))
    resolve(point, found, MAPS["0ba8"])  # the V area is alike in every generation
    return found


def _block(name: str, number: int, data_type: str) -> LogoAddress:
    """Return a block address after checking its number and type against every generation."""
    most = max(table[name].count for table in MAPS.values() if name in table)
    if not 1 <= number <= most:
        raise PlcAddressError(f"{name}{number}: a LOGO! has {name}1 to {name}{most} at most")
    analog = name.startswith(("A", "NA"))
    wanted = ANALOG_TYPES if analog else ("BOOL",)
    if data_type not in wanted:
        raise PlcAddressError(
            f"{name}{number} is an {_WHAT[name]}: read it as {' or '.join(wanted)}"
            if analog
            else f"{name}{number} is a {_WHAT[name]}: read it as BOOL"
        )
    return LogoAddress(name, number)


def resolve(point: Point, found: LogoAddress, blocks: dict[str, Block]) -> Variable:
    """Return the DB1 variable of an address in one generation's map; raise PlcAddressError."""
    data_type = normalize_type(point.data_type)
    if found.block == "V":
        spelled = found.text if found.width else f"V{found.number}.{found.bit}"
        s7 = s7_variable(Point(spelled, data_type))
        if s7.start + s7.size > VM_USER:
            raise PlcAddressError(
                f"{found.text}: a {data_type} there runs past V{VM_USER - 1}, the end of the VM "
                "a program's blocks use"
            )
        return Variable(AREA_DB, VM_DB, s7.start, data_type, s7.bit, found.text)
    block = blocks.get(found.block)
    if block is None or found.number > block.count:
        has = f"has {found.block}1 to {found.block}{block.count}" if block else "has none"
        raise PlcAddressError(f"{found.text}: this LOGO! generation {has}")
    index = found.number - 1
    if block.analog:
        return Variable(AREA_DB, VM_DB, block.start + 2 * index, data_type, None, found.text)
    return Variable(AREA_DB, VM_DB, block.start + index // 8, data_type, index % 8, found.text)


def variable(point: Point, generation: str) -> Variable:
    """Resolve a point for a LOGO! of one generation; raise PlcAddressError."""
    return resolve(point, parse(point), MAPS[generation])


def refusal(found: LogoAddress) -> str | None:
    """Why a client cannot write the address; None where it can."""
    return _REFUSED.get(found.block)


def shift(point: Point, by: int, unit: str) -> Point:
    """Return a point moved by `by` bytes of VM or by `by` block numbers; raise PlcAddressError.

    By bytes, VM moves by its bytes (V10.3 + 2 = V12.3), and a block by its image's bytes in
    VM: 8 bits to a byte (I1 + 1 byte = I9), an analog word 2 (AI1 + 2 bytes = AI2, an odd
    count refused). By blocks, a block moves by its number (I1 + 4 = I5); VM has no blocks.
    The moved address is checked as typed (a block number some generation has, VM below 850).
    """
    found = parse(point)
    if found.block == "V":
        if unit != BYTES:
            raise PlcAddressError(f"{found.text} is VM: it moves by bytes, not by block numbers")
        offset = found.number + by
        if offset < 0:
            raise PlcAddressError(f"{found.text} + {by} bytes falls below V0")
        moved = replace(found, number=offset)
    elif unit == BLOCKS:
        moved = replace(found, number=found.number + by)
    elif unit == BYTES:
        per_byte = 0.5 if found.block.startswith(("A", "NA")) else 8
        if (by * per_byte) % 1:
            raise PlcAddressError(f"{found.text} is an analog word: move it by an even count")
        moved = replace(found, number=found.number + int(by * per_byte))
    else:
        raise PlcAddressError(f"{found.text}: a LOGO! address moves by bytes or block numbers")
    if moved.number < (0 if moved.block == "V" else 1):
        raise PlcAddressError(f"{found.text} + {by} {unit} falls below {found.block}1")
    shifted = Point(moved.text, point.data_type)
    parse(shifted)
    return shifted
