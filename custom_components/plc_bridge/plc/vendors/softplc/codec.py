"""SoftPLC point types and values: which types an address takes, words in and out.

The datatable holds 16-bit integer words and IEEE 32-bit floats (manual 4). Replies print words
in decimal or hex ("0x0000", "42 63293": a word written 0xf73d comes back unsigned); a request
takes either. The manual lists no string type, so there is none here.
"""

from __future__ import annotations

import math
import re
import struct

from ...codec import check_bool, check_float, check_integer, plain_decimal, shortest_real
from ...errors import PlcAddressError, PlcProtocolError, PlcValueError
from ...types import Value, ValueKind
from .address import FLOAT_TYPES, Address

TYPES = ("INT", "UINT", "WORD", "REAL", "BOOL")
"""A signed word, an unsigned word, an unsigned word shown in hex on input, a float, a bit."""
KINDS: dict[str, ValueKind] = {
    "INT": ValueKind.INTEGER,
    "UINT": ValueKind.INTEGER,
    "WORD": ValueKind.INTEGER,
    "REAL": ValueKind.FLOAT,
    "BOOL": ValueKind.BOOL,
}
_HEX = re.compile(r"[+-]?0[xX][0-9a-fA-F]{1,8}")
_DECIMAL = re.compile(r"[+-]?[0-9]{1,20}")
_FLOAT = re.compile(r"[+-]?(?:[0-9]{1,40}\.?[0-9]{0,40}|\.[0-9]{1,40})(?:[eE][+-]?[0-9]{1,3})?")
_COMMA = re.compile(r"[+-]?(?:[0-9]{1,40},[0-9]{0,40}|,[0-9]{1,40})(?:[eE][+-]?[0-9]{1,3})?")
"""A decimal comma: C's printf under a localised LC_NUMERIC (READINGS.md, row 15)."""


def default_type(address: Address) -> str:
    """Return the type an address holds when the point names none."""
    if address.bit is not None:
        return "BOOL"
    if address.type in FLOAT_TYPES or address.is_named_word:
        return "REAL"
    return "INT"


def data_type(address: Address, text: str) -> str:
    """Return the point's type, upper case (the address's own when empty); raise when unfit."""
    kind = (text or "").strip().upper() or default_type(address)
    if kind not in TYPES:
        raise PlcAddressError(f"{text!r} is not a SoftPLC data type; use {', '.join(TYPES)}")
    if address.is_tag:
        return kind  # the descriptor table, not the address, says what a tag holds
    if (kind == "BOOL") != (address.bit is not None):
        raise PlcAddressError(f"{address.text}: BOOL is for bits (B3:0/5) and bits only")
    if address.type in FLOAT_TYPES and kind != "REAL":
        raise PlcAddressError(f"{address.text} is a float: use REAL")
    if kind == "REAL" and address.type not in FLOAT_TYPES and not address.is_named_word:
        raise PlcAddressError(f"{address.text} is an integer word: use INT, UINT or WORD")
    return kind


def parse_token(token: str, what: str) -> int | float:
    """Return one printed value: decimal or 0x hex integer, or a float (point or comma).

    A comma is read as a decimal comma only where it is the one separator: a token with a
    point and a comma (grouped digits, "1.234,5") could mean two numbers and is refused.
    """
    if _HEX.fullmatch(token):
        return int(token, 16)
    if _DECIMAL.fullmatch(token):
        return int(token)
    if _FLOAT.fullmatch(token) or token.lower().lstrip("+-") in ("nan", "inf", "infinity"):
        return float(token)
    if _COMMA.fullmatch(token):
        return float(token.replace(",", "."))
    raise PlcProtocolError(f"{what}: the PLC answered {token[:20]!r}, not a number")


def printed_unit(token: str) -> float:
    """Return the value of the last digit a float was printed with ("22.30" 0.01, "2.2e1" 1)."""
    mantissa, _e, exponent = token.lower().partition("e")
    decimals = len(mantissa.replace(",", ".").partition(".")[2])
    try:
        return float(10 ** (int(exponent or "0") - decimals))
    except (ValueError, OverflowError):
        return 0.0


def decode(kind: str, raw: int | float, bit: int | None, what: str) -> Value:
    """Return a point's value from its word (and bit) as the PLC printed it."""
    if kind == "REAL":
        value = float(raw)
        return shortest_real(value) if math.isfinite(value) else value
    if isinstance(raw, float):
        if not raw.is_integer():
            raise PlcProtocolError(f"{what}: the PLC answered {raw!r} for an integer word")
        raw = int(raw)
    if not -0x8000 <= raw <= 0xFFFF:
        raise PlcProtocolError(f"{what}: the PLC answered {raw}, more than a word holds")
    word = raw & 0xFFFF
    if kind == "BOOL":
        return bool(word >> (bit or 0) & 1)
    if kind == "INT":
        return word - 0x10000 if word & 0x8000 else word
    return word


def check_value(kind: str, value: Value, what: str) -> Value:
    """Return a value checked for the type: decimal or hex text for words, finite REALs."""
    if kind == "BOOL":
        return check_bool(value, what)
    if kind == "REAL":
        return check_float(value, what=what)
    if isinstance(value, str) and _HEX.fullmatch(value.strip()):
        value = int(value.strip(), 16)
    low, high = (-0x8000, 0x7FFF) if kind == "INT" else (0, 0xFFFF)
    return check_integer(value, low, high, what)


def word_of(kind: str, value: Value) -> int:
    """Return the 16-bit pattern a checked integer value is written as."""
    if isinstance(value, bool) or not isinstance(value, int):
        raise PlcValueError(f"{value!r} is not a whole number")
    return value & 0xFFFF


def encode_word(word: int) -> str:
    """Return a word as a request carries it: decimal up to 32767, else hex (0xF73D).

    The manual shows both forms written to an N file ("42 0xf73d"); a negative decimal is
    not shown, and a firmware reading words as signed might refuse 63293 in decimal.
    """
    return str(word) if word < 0x8000 else f"0x{word:04X}"


def encode_float(value: float) -> str:
    """Return a float as plain decimal text (never 1e+10: the manual shows no exponents)."""
    return plain_decimal(shortest_real(value))


def same_float(sent: float, answered: float, unit: float = 0.0) -> bool:
    """True when an answer is the IEEE single sent, as far as its printed digits (`unit`) show.

    "22.3", "22.299999", "2.230000e+01" and "22.2999992" all show the single 22.3 is stored;
    "1235" could be 1234.5678 printed with four digits (whether it is, `confirm` decides).
    """
    try:
        stored: float = struct.unpack("<f", struct.pack("<f", sent))[0]
        if struct.pack("<f", answered) == struct.pack("<f", stored):
            return True
    except (OverflowError, struct.error):
        return False
    return abs(answered - stored) <= unit / 2 + 4 * math.ulp(max(abs(answered), abs(stored)))
