"""S7 addresses as STEP 7 / TIA Portal show them, and the data types each width takes.

python-snap7's tag parser (`snap7.tags.parse_tag`, 3.3.0) is not used: its `Area` knows only
DB, M, I and Q, so it rejects V (S7-200 memory), T, C, PIW/PQW and the German E/A/Z spellings;
bare forms such as `M10.1` or `IW64` need `strict=False`, and it accepts what a CPU refuses
(`DB1.DBW4:REAL`, bit 9 in `DB1.DBX0.9`). The point form needs those refused with a hint.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import lru_cache
import re

from ...errors import PlcAddressError
from ...shifting import BYTES, DATA_BLOCKS
from ...types import Point, ValueKind

AREA_P = 0x80  # peripheral I/O: reads reach the inputs, writes the outputs
AREA_I = 0x81
AREA_Q = 0x82
AREA_M = 0x83
AREA_DB = 0x84
AREA_C = 0x1C
AREA_T = 0x1D
AREA_C200 = 0x1E  # an S7-200 (CP 243-1) serves its counters and timers under codes of its own
AREA_T200 = 0x1F
COUNTED = (AREA_C, AREA_T, AREA_C200, AREA_T200)  # addressed by number, two bytes each
V_DB = 1  # an S7-200 (CP 243-1) serves V memory as DB1 over S7comm

DATA_TYPES: tuple[str, ...] = (
    "BOOL",
    "BYTE",
    "CHAR",
    "WORD",
    "INT",
    "UINT",
    "DWORD",
    "DINT",
    "UDINT",
    "REAL",
    "LREAL",
    "STRING",
    "DATE_AND_TIME",
    "DTL",
    "SINT",
    "USINT",
    "LINT",
    "ULINT",
    "LWORD",
    "TIME",
    "S5TIME",
    "TIME_OF_DAY",
    "DATE",
    "WCHAR",
    "WSTRING",
    "COUNTER",
)
"""The point form's data types; STRING and WSTRING (read as [254]) and [n] forms are accepted.

A write never trusts either length: it reads the STRING's or WSTRING's header in the PLC first.
COUNTER is a counter's value as the CPU keeps it: three BCD digits (0..999) in a word.
"""

STRING_MAX = 254
WSTRING_MAX = 16382
SIZES: dict[str, int] = {
    "BOOL": 1,
    "BYTE": 1,
    "CHAR": 1,
    "SINT": 1,
    "USINT": 1,
    "WORD": 2,
    "INT": 2,
    "UINT": 2,
    "S5TIME": 2,
    "DATE": 2,
    "WCHAR": 2,
    "COUNTER": 2,
    "DWORD": 4,
    "DINT": 4,
    "UDINT": 4,
    "REAL": 4,
    "TIME": 4,
    "TIME_OF_DAY": 4,
    "LREAL": 8,
    "LINT": 8,
    "ULINT": 8,
    "LWORD": 8,
    "DATE_AND_TIME": 8,
    "DTL": 12,
}
KINDS: dict[str, ValueKind] = {
    "BOOL": ValueKind.BOOL,
    **dict.fromkeys(
        ("BYTE", "WORD", "INT", "UINT", "DWORD", "DINT", "UDINT", "SINT", "USINT", "LINT"),
        ValueKind.INTEGER,
    ),
    **dict.fromkeys(("ULINT", "LWORD", "COUNTER"), ValueKind.INTEGER),
    "REAL": ValueKind.FLOAT,
    "LREAL": ValueKind.FLOAT,
    **dict.fromkeys(("CHAR", "STRING", "WCHAR", "WSTRING"), ValueKind.TEXT),
    **dict.fromkeys(("DATE_AND_TIME", "DTL", "DATE"), ValueKind.DATETIME),
    **dict.fromkeys(("TIME", "S5TIME", "TIME_OF_DAY"), ValueKind.DURATION),
}
# Types longer than a double word have no width letter in STEP 7: they take their first byte.
_FROM_BYTE = ("LREAL", "LINT", "ULINT", "LWORD", "STRING", "WSTRING", "DATE_AND_TIME", "DTL")
_FITS: dict[str, tuple[str, ...]] = {
    "X": ("BOOL",),
    "B": ("BYTE", "CHAR", "SINT", "USINT", *_FROM_BYTE),
    "W": ("WORD", "INT", "UINT", "S5TIME", "DATE", "WCHAR", "COUNTER"),
    "D": ("DWORD", "DINT", "UDINT", "REAL", "TIME", "TIME_OF_DAY"),
}
_HOLDS = {
    "X": "BOOL",
    "B": "BYTE, CHAR, SINT or USINT, or the first byte of an LREAL, LINT, ULINT, LWORD, "
    "STRING, WSTRING, DATE_AND_TIME or DTL",
    "W": "WORD, INT, UINT, S5TIME, DATE, WCHAR or COUNTER",
    "D": "DWORD, DINT, UDINT, REAL, TIME or TIME_OF_DAY",
}
_WIDTH_NAMES = {
    "X": "a bit",
    "B": "a byte",
    "W": "a word (16 bits)",
    "D": "a double word (32 bits)",
}
_ALIASES = {
    "E": "I",
    "A": "Q",
    "PE": "PI",
    "PA": "PQ",
    "Z": "C",
    "DT": "DATE_AND_TIME",
    "TOD": "TIME_OF_DAY",
}
# A CPU cannot read PQ (STEP 7 only transfers to it); a PQ write also updates the process
# image, so PQ is read there.
_AREAS = {"I": AREA_I, "Q": AREA_Q, "M": AREA_M, "V": AREA_DB, "PI": AREA_P, "PQ": AREA_Q}
_N = "[0-9]{1,9}"  # ASCII digits (\d takes any script's), few enough for int() (4,300 at most)
_PATTERN = re.compile(
    rf"%?(?:DB(?P<db>{_N})\.DB(?P<dbwidth>[XBWD])(?P<dboffset>{_N})(?:\.(?P<dbbit>{_N}))?"
    rf"|(?P<area>PI|PE|PQ|PA|I|E|Q|A|M|V)(?P<width>[BWD]?)(?P<offset>{_N})(?:\.(?P<bit>{_N}))?"
    rf"|(?P<counter>T|C|Z)(?P<number>{_N}))"
)
_STRING = re.compile(rf"(W?)STRING\[({_N})\]")
EXAMPLES = "DB1.DBX0.0, DB1.DBW4, M10.1, MW20, IW64, Q0.1, PIW256, VW100, T5 or C3"
MAX_OFFSET = 0xFFFF


@dataclass(frozen=True, slots=True)
class Variable:
    """A point resolved to the wire: area, DB, first byte (T/C: number), bit, size, type."""

    area: int
    db: int
    start: int
    data_type: str  # normalized, e.g. INT or STRING[20]
    bit: int | None = None
    text: str = ""  # the normalized address
    write_area: int = 0  # where writes go when not to `area` (PQ: the peripheral outputs)

    @property
    def counted(self) -> bool:
        """True for timers and counters, addressed by number (two bytes each), not by byte."""
        return self.area in COUNTED

    @property
    def wide(self) -> bool:
        """True for a WSTRING: two-byte lengths and UTF-16 characters."""
        return self.data_type.startswith("WSTRING")

    @property
    def string_length(self) -> int:
        """The declared maximum length of a STRING or WSTRING in characters (0 for others)."""
        if self.data_type in ("STRING", "WSTRING"):
            return STRING_MAX
        match = _STRING.fullmatch(self.data_type)
        return int(match[2]) if match else 0

    @property
    def header_size(self) -> int:
        """Bytes of a string's header: maximum and current length (one byte each, WSTRING two)."""
        return 4 if self.wide else 2

    @property
    def size(self) -> int:
        """How many bytes the value takes in the PLC (T/C: one element)."""
        if self.string_length:
            return self.header_size + self.string_length * (2 if self.wide else 1)
        return SIZES[self.data_type]


def on_s7_200(found: Variable) -> Variable:
    """Return a timer or counter with the S7-200's area codes; any other variable as it is."""
    if found.area == AREA_T:
        return replace(found, area=AREA_T200)
    if found.area == AREA_C:
        return replace(found, area=AREA_C200)
    return found


def normalize_type(data_type: str) -> str:
    """Return the canonical type name; STRING[254] is STRING; raise PlcAddressError."""
    name = re.sub(r"\s+", "", data_type).upper()
    name = _ALIASES.get(name, name)
    if match := _STRING.fullmatch(name):
        base, length = f"{match[1]}STRING", int(match[2])
        limit = WSTRING_MAX if match[1] else STRING_MAX
        if not 1 <= length <= limit:
            raise PlcAddressError(f"a {base} holds 1..{limit} characters, not {length}")
        return base if length == STRING_MAX else f"{base}[{length}]"
    if name not in SIZES and name not in ("STRING", "WSTRING"):
        raise PlcAddressError(
            f"{data_type!r} is not an S7 data type; use {', '.join(DATA_TYPES)}, STRING[n] "
            "or WSTRING[n]"
        )
    return name


def value_kind(data_type: str) -> ValueKind | None:
    """What a data type's values are (None for an unknown type)."""
    try:
        name = normalize_type(data_type)
    except PlcAddressError:
        return None
    return KINDS[_base(name)]


def _base(data_type: str) -> str:
    """Return a type without its length (WSTRING[20] -> WSTRING)."""
    return data_type.partition("[")[0]


@lru_cache(maxsize=8192)
def variable(point: Point) -> Variable:
    """Resolve a point; raise PlcAddressError with a message the point form can show."""
    data_type = normalize_type(point.data_type)
    text = re.sub(r"\s+", "", point.address).upper()
    match = _PATTERN.fullmatch(text)
    if match is None:
        raise PlcAddressError(f"{point.address!r} is not an S7 address; try {EXAMPLES}")
    if match["counter"]:
        return _counted(match["counter"], int(match["number"]), data_type)
    if match["db"]:
        db = int(match["db"])
        if not 1 <= db <= 0xFFFF:
            raise PlcAddressError(f"{point.address!r}: DB numbers run from 1 to 65535")
        width, offset, bit = match["dbwidth"], int(match["dboffset"]), match["dbbit"]
        area, prefix = AREA_DB, f"DB{db}.DB"
    else:
        name = _ALIASES.get(match["area"], match["area"])
        width, offset, bit = match["width"] or "X", int(match["offset"]), match["bit"]
        area, prefix, db = _AREAS[name], name, V_DB if name == "V" else 0
        if name in ("PI", "PQ") and not match["width"]:
            raise PlcAddressError(
                f"{point.address!r}: peripheral I/O is read by byte, word or double word "
                f"({name}B, {name}W, {name}D), not by bit"
            )
    place = _place(point.address, prefix, width, offset, bit)
    _check_fit(place, width, data_type)
    found = Variable(area, db, offset, data_type, None if bit is None else int(bit), place)
    if prefix == "PQ":
        found = replace(found, write_area=AREA_P)
    if found.start + found.size - 1 > MAX_OFFSET:
        raise PlcAddressError(f"{place}: a {data_type} there runs past byte {MAX_OFFSET}")
    return found


def _place(address: str, prefix: str, width: str, offset: int, bit: str | None) -> str:
    """Return the normalized address text after checking the bit number against the width."""
    if offset > MAX_OFFSET:
        raise PlcAddressError(f"{address!r}: byte offsets run from 0 to {MAX_OFFSET}")
    if width == "X":
        if bit is None:
            raise PlcAddressError(
                f"{address!r} needs a bit number or a width, e.g. {prefix}{offset}.0 "
                f"or {prefix}B{offset}"
                if not prefix.startswith("DB")
                else f"{address!r} needs a bit number, e.g. {prefix}X{offset}.0"
            )
        if int(bit) > 7:
            raise PlcAddressError(f"{address!r}: bit numbers run from 0 to 7")
        return f"{prefix}{'X' if prefix.startswith('DB') else ''}{offset}.{int(bit)}"
    if bit is not None:
        raise PlcAddressError(f"{address!r}: {_WIDTH_NAMES[width]} address takes no bit number")
    return f"{prefix}{width}{offset}"


def _check_fit(place: str, width: str, data_type: str) -> None:
    """Refuse a data type that does not fit the address width (DBW + REAL and the like)."""
    base = _base(data_type)
    if base in _FITS[width]:
        return
    if base in _FROM_BYTE:
        hint = f"give its first byte, e.g. {_with_width(place, 'B')}"
    else:
        wanted = next(letter for letter, types in _FITS.items() if base in types)
        hint = f"use {_with_width(place, wanted)}"
    raise PlcAddressError(
        f"{place} is {_WIDTH_NAMES[width]} for {_HOLDS[width]}; for {base} {hint}"
    )


def _with_width(place: str, width: str) -> str:
    """Return the same byte offset spelled with another width letter (DB1.DBW4 -> DB1.DBD4)."""
    match = re.fullmatch(rf"(DB{_N}\.DB|[A-Z]+?)([XBWD]?)({_N})(?:\.[0-9])?", place)
    assert match is not None
    prefix, offset = match[1], match[3]
    if width == "X":
        return f"{prefix}{'X' if prefix.startswith('DB') else ''}{offset}.0"
    return f"{prefix}{width}{offset}"


def _counted(letter: str, number: int, data_type: str) -> Variable:
    """Return a timer (WORD or S5TIME) or counter (WORD or COUNTER) variable."""
    name = _ALIASES.get(letter, letter)
    if number > MAX_OFFSET:
        raise PlcAddressError(f"{name}{number}: numbers run from 0 to {MAX_OFFSET}")
    typed = "S5TIME" if name == "T" else "COUNTER"
    if data_type not in ("WORD", typed):
        raise PlcAddressError(
            f"{name}{number} is a {'timer' if name == 'T' else 'counter'}: read it as {typed} "
            "or as WORD (the raw word the CPU keeps)"
        )
    return Variable(
        AREA_T if name == "T" else AREA_C, 0, number, data_type, None, f"{name}{number}"
    )


def shift(point: Point, by: int, unit: str) -> Point:
    """Return a point moved by `by` bytes, or `by` DB numbers; raise PlcAddressError.

    A bit moves with its byte (DB10.DBX0.3 + 24 bytes = DB10.DBX24.3); timers and counters,
    numbered rather than addressed by byte, do not move by bytes; only DB addresses move by
    DB numbers. The moved address is checked as typed (its end within byte 65535, DB 1..65535).
    """
    found = variable(point)
    if unit == DATA_BLOCKS:
        if found.area != AREA_DB or found.text.startswith("V"):
            raise PlcAddressError(f"{found.text} is in no data block: it does not move by DBs")
        moved = re.sub(rf"^DB{found.db}\.", f"DB{found.db + by}.", found.text)
        if not 1 <= found.db + by <= 0xFFFF:
            raise PlcAddressError(f"{moved}: DB numbers run from 1 to 65535")
    elif unit == BYTES:
        if found.counted:
            raise PlcAddressError(f"{found.text} is numbered, not addressed by byte")
        match = re.fullmatch(rf"(DB{_N}\.DB[XBWD]|[A-Z]+?[BWD]?)({_N})(\.[0-7])?", found.text)
        assert match is not None  # every normalized byte address is spelled so
        offset = found.start + by
        moved = f"{match[1]}{offset}{match[3] or ''}"
        if offset < 0:
            raise PlcAddressError(f"{found.text} + {by} bytes falls below byte 0")
    else:
        raise PlcAddressError(f"{found.text}: an S7 address moves by bytes or DB numbers")
    return Point(variable(Point(moved, found.data_type)).text, point.data_type)
