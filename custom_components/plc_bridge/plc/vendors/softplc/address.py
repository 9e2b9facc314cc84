"""SoftPLC datatable addresses and tag names: parse, check, spell as requests, read replies.

The manual (4, "Quick review of the SoftPLC datatable") defines `<type><file>:<element>` with
the type in one or two letters (N7:3, PD12:3000), a word of a structured element after a period
(T4:0.PRE, PD12:3000.SP), up to 10,000 files, and normalised replies (N0007:0033, O:0000,
I:0001). Requests carry the manual's request forms (N7:33, I1:3: file number included), never
a reply's form (I:3). Where it is silent we follow the PLC-5 layout, said so below.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
import re

from ...errors import PlcAddressError
from ...shifting import ELEMENTS

MAX_FILE = 9999  # "the top most array can hold up to 10,000 sub-arrays"
MAX_ELEMENT = 99999  # the manual shows PD12:3000; no upper bound is given
FIXED_FILES: dict[str, int] = {"O": 0, "I": 1, "S": 2}
"""Files at a fixed position, written without their number in replies ("O:0000", "I:0001").

The manual's POST example asks for "O0" and "I1" and is answered "O:0000" with 8 values and
"I:0001" with 7: the digits may be the element (I1 is I:1, PLC-5 style) or the file (I1 is
I1:0, as "N7" is N7:0). Such an address without a colon is sent as typed, alone, and its
first value taken: whichever the PLC reads, the point is what the PLC calls it
(simulators/softplc/READINGS.md, "O3, I1 without a colon").
"""
WORDS_PER_ELEMENT: dict[str, int] = {"T": 3, "C": 3, "R": 3}
"""Timers, counters and controls "consist of 3 words each" (manual 4); every other type one."""
STRUCTURE_WORDS: dict[str, dict[str, int]] = {
    "T": {"PRE": 1, "ACC": 2},
    "C": {"PRE": 1, "ACC": 2},
    "R": {"LEN": 1, "POS": 2},
}
"""Word names of a 3-word element. The manual names T4:0.PRE; the rest is the PLC-5 layout:
word 0 holds the status bits, then the preset (length) and the accumulator (position)."""
STATUS_BITS: dict[str, dict[str, int]] = {
    "T": {"EN": 15, "TT": 14, "DN": 13},
    "C": {"CU": 15, "CD": 14, "DN": 13, "OV": 12, "UN": 11},
    "R": {"EN": 15, "EU": 14, "DN": 13, "EM": 12, "ER": 11, "UL": 10, "IN": 9, "FD": 8},
}
"""Status bits in word 0 of timers, counters and controls (PLC-5 layout; the manual is silent)."""
FLOAT_TYPES = ("F",)
WORD_TYPES = ("O", "I", "S", "B", "N", "F", "T", "C", "R")
"""Types read as ranges of elements; PD elements (a mix of integers and floats whose layout the
manual does not give) are read and written one named word at a time (PD12:3000.SP)."""
EXAMPLES = (
    "N7:3, N7:3/4, B3:0/5, B3/37, F8:2, T4:0.PRE, T4:0.DN, C5:1.ACC, O0:0, I1:1, S2:5, PD12:3000.SP"
)

_PATTERN = re.compile(
    r"(?P<type>PD|[OISBTCRNF])(?P<file>[0-9]{1,6})?(?::(?P<element>[0-9]{1,6}))?"
    r"(?:\.(?P<word>[A-Z]{1,8}|[0-9]{1,2}))?(?:/(?P<bit>[0-9]{1,7}))?"
)
_TAG = re.compile(r"[A-Za-z_][A-Za-z0-9_.]{0,63}")


@dataclass(frozen=True, slots=True)
class Address:
    """A datatable word (or bit, or named PD word), or a tag from the descriptor table."""

    type: str  # O I S B T C R N F PD; "" for a tag
    file: int = 0
    element: int = 0
    word: int = 0  # word of a 3-word element (T, C, R); 0 otherwise
    bit: int | None = None
    name: str = ""  # the PD word's name (SP), or the tag
    bit_name: str = ""  # T4:0.DN: the status bit's name, kept for the text
    typed: str = ""  # O3, I1: a fixed file's address without a colon, sent as typed

    @property
    def is_opaque(self) -> bool:
        """True for O3 or I1 (no colon): its element is the PLC's reading, so it is sent alone."""
        return bool(self.typed)

    @property
    def ad(self) -> str:
        """The `ad` that reads this address alone: the tag, O3 as typed, or the element."""
        if self.is_tag:
            return self.name
        if self.typed:
            return self.typed
        return self.text if self.is_named_word else element_ad(self.type, self.file, self.element)

    @property
    def identity(self) -> tuple[str, int, int, str]:
        """What tells two addresses apart: tags by their exact name (case kept)."""
        if self.is_tag:
            return "", 0, 0, self.name
        if self.typed:
            return "?", 0, 0, self.typed
        return self.type, self.file, self.element, self.suffix

    @property
    def is_tag(self) -> bool:
        """True for a tag name of the descriptor table instead of an address."""
        return not self.type

    @property
    def is_named_word(self) -> bool:
        """True for a PD word (PD12:3000.SP), read and written by its own name."""
        return self.type == "PD"

    @property
    def text(self) -> str:
        """The address in the manual's request form (upper case, file number, no zeros)."""
        if self.is_tag:
            return self.name
        if self.typed:
            return self.typed if self.bit is None else f"{self.typed}/{self.bit}"
        text = element_ad(self.type, self.file, self.element)
        if self.name:
            return f"{text}.{self.name}"
        if self.bit_name:
            return f"{text}.{self.bit_name}"
        if self.suffix:
            text = f"{text}.{self.suffix}"
        return text if self.bit is None else f"{text}/{self.bit}"

    @property
    def suffix(self) -> str:
        """The word's name after the period (SP, PRE), "" for a whole element."""
        return self.name if self.is_named_word else word_name(self.type, self.word)

    @property
    def range_key(self) -> tuple[str, int]:
        """The file this address lies in, for merging neighbours into one range."""
        return self.type, self.file

    @property
    def words(self) -> int:
        """Words per element of the address's file."""
        return WORDS_PER_ELEMENT.get(self.type, 1)


def element_ad(type_: str, file: int, element: int) -> str:
    """Return the `ad` of an element in the request form (N7:33, O0:0, I1:3)."""
    return f"{type_}{file}:{element}"


def parse_address(text: str) -> Address:
    """Parse an address or tag name; raise PlcAddressError with a message for a form."""
    if not isinstance(text, str):
        raise PlcAddressError(f"{text!r} is not a SoftPLC address")
    stripped = text.strip()
    match = _PATTERN.fullmatch(stripped.upper())
    if match is None:
        if _TAG.fullmatch(stripped):
            return Address("", name=stripped)
        raise PlcAddressError(f"{text!r} is not a SoftPLC address or tag name; try {EXAMPLES}")
    return _checked(text, match)


def _checked(text: str, match: re.Match[str]) -> Address:
    """Turn a pattern match into an Address; refuse what the file type does not allow."""
    type_, file_digits, element_digits = match["type"], match["file"], match["element"]
    word, bit_digits = match["word"], match["bit"]
    typed = ""
    if type_ in FIXED_FILES:
        fixed = FIXED_FILES[type_]
        if element_digits is None:  # O3: the PLC's reading decides (see FIXED_FILES)
            if word is not None:
                raise PlcAddressError(f"{text!r}: write the element, as {type_}{fixed}:0")
            typed = f"{type_}{file_digits or ''}"
            element_digits, file_digits = file_digits or "0", None
        if file_digits is not None and int(file_digits) != fixed:
            raise PlcAddressError(f"{text!r}: the {type_} file is file {fixed}")
        file = fixed
    elif file_digits is None:
        raise PlcAddressError(f"{text!r} names no file number ({type_}7:0, not {type_}:0)")
    else:
        file = int(file_digits)
    if file > MAX_FILE:
        raise PlcAddressError(f"{text!r}: files are numbered 0 to {MAX_FILE}")
    element = int(element_digits or 0)
    bit = None if bit_digits is None else int(bit_digits)
    if element_digits is None and bit is not None and word is None:
        element, bit = divmod(bit, 16)  # B3/37 is B3:2/5: bits counted through the file
    if element > MAX_ELEMENT:
        raise PlcAddressError(f"{text!r}: elements are numbered 0 to {MAX_ELEMENT}")
    if bit is not None and bit > 15:
        raise PlcAddressError(f"{text!r}: a word has bits 0 to 15")
    if typed:
        return Address(type_, file, element, bit=bit, typed=typed)
    if type_ == "PD":
        if word is None or word.isdigit() or bit is not None:
            raise PlcAddressError(f"{text!r}: a PID element is read by word, as PD12:3000.SP")
        return Address(type_, file, element, name=word)
    if word is not None:
        return _structure_word(text, Address(type_, file, element), word, bit)
    if type_ in FLOAT_TYPES and bit is not None:
        raise PlcAddressError(f"{text!r}: a float has no bits")
    return Address(type_, file, element, bit=bit)


def _structure_word(text: str, base: Address, word: str, bit: int | None) -> Address:
    """Return the word (T4:0.PRE) or status bit (T4:0.DN) of a timer, counter or control."""
    type_, file, element = base.type, base.file, base.element
    if type_ not in STRUCTURE_WORDS:
        raise PlcAddressError(f"{text!r}: only T, C, R and PD elements have words")
    if word.isdigit():
        if int(word) >= WORDS_PER_ELEMENT[type_]:
            raise PlcAddressError(f"{text!r}: a {type_} element has words 0 to 2")
        return Address(type_, file, element, word=int(word), bit=bit)
    if word in STRUCTURE_WORDS[type_]:
        return Address(type_, file, element, word=STRUCTURE_WORDS[type_][word], bit=bit)
    if word in STATUS_BITS[type_] and bit is None:
        return Address(type_, file, element, bit=STATUS_BITS[type_][word], bit_name=word)
    names = ", ".join([*STRUCTURE_WORDS[type_], *STATUS_BITS[type_]])
    raise PlcAddressError(f"{text!r}: a {type_} element has {names}")


def reply_key(ad: str) -> tuple[str, int, int, str] | None:
    """Return the datatable place a reply's `ad` names (type, file, element, word name).

    N0007:0033 and N7:33 give the same key, I:0001 and I1:1 too. None for a tag, for O3 or I1
    without a colon (their element is the PLC's reading), and for text that is neither.
    """
    try:
        address = parse_address(ad)
    except PlcAddressError:
        return None
    if address.is_tag or address.is_opaque:
        return None
    return address.type, address.file, address.element, address.suffix


def opaque_keys(address: Address) -> frozenset[tuple[str, int, int, str]]:
    """Return the places a reply may name for O3 or I1: the element, or the file's element 0."""
    keys = {(address.type, address.file, address.element, "")}
    if address.element == address.file:  # I1 read as file I1, element 0
        keys.add((address.type, address.file, 0, ""))
    return frozenset(keys)


def word_name(type_: str, word: int) -> str:
    """Return the name of word `word` of a T, C or R element ("" for word 0)."""
    return next((k for k, v in STRUCTURE_WORDS.get(type_, {}).items() if v == word), "")


def shift(text: str, by: int, unit: str) -> str:
    """Return an address moved by `by` elements of its file (N7:10 + 5 = N7:15, B3:0/5 too).

    A timer's word or bit moves with its element (T4:0.PRE + 1 = T4:1.PRE). Tags, and O3 or I1
    without a colon (whose element is the PLC's reading), do not move. The moved address is
    checked as typed. Raise PlcAddressError.
    """
    address = parse_address(text)
    if unit != ELEMENTS:
        raise PlcAddressError(f"{address.text}: a SoftPLC address moves by elements")
    if address.is_tag:
        raise PlcAddressError(f"{address.text} is a tag name: it has no element to move")
    if address.is_opaque:
        raise PlcAddressError(f"{address.text}: write its element ({address.type}1:3) to move it")
    if address.element + by < 0:
        raise PlcAddressError(f"{address.text} + {by} elements falls below element 0")
    return parse_address(replace(address, element=address.element + by).text).text
