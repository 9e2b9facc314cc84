"""Value checks and encodings shared by vendors: IEC integer ranges, REAL, BOOL, ASCII text."""

from __future__ import annotations

from collections.abc import Callable, Collection, Mapping
from datetime import datetime, tzinfo
from decimal import Decimal
import math
import re
import struct

from .errors import PlcAddressError, PlcProtocolError, PlcValueError
from .types import Value, ValueKind

INTEGER_RANGES: dict[str, tuple[int, int]] = {
    "BYTE": (0, 0xFF),
    "WORD": (0, 0xFFFF),
    "DWORD": (0, 0xFFFF_FFFF),
    "LWORD": (0, 0xFFFF_FFFF_FFFF_FFFF),
    "USINT": (0, 0xFF),
    "UINT": (0, 0xFFFF),
    "UDINT": (0, 0xFFFF_FFFF),
    "ULINT": (0, 0xFFFF_FFFF_FFFF_FFFF),
    "SINT": (-0x80, 0x7F),
    "INT": (-0x8000, 0x7FFF),
    "DINT": (-0x8000_0000, 0x7FFF_FFFF),
    "LINT": (-0x8000_0000_0000_0000, 0x7FFF_FFFF_FFFF_FFFF),
}
"""Inclusive value range of each IEC 61131-3 integer and bit-string type."""

REAL_MAX = 3.4028234663852886e38

IEC_KINDS: dict[str, ValueKind] = {
    "BOOL": ValueKind.BOOL,
    **dict.fromkeys(INTEGER_RANGES, ValueKind.INTEGER),
    "REAL": ValueKind.FLOAT,
    "LREAL": ValueKind.FLOAT,
    **dict.fromkeys(("STRING", "WSTRING", "CHAR", "WCHAR"), ValueKind.TEXT),
    **dict.fromkeys(("DATE", "DT", "DATE_AND_TIME", "LDT"), ValueKind.DATETIME),
}
"""The kind of value of the IEC 61131-3 elementary types a vendor may use as data types."""

CHECKED = frozenset(("BOOL", *INTEGER_RANGES, "REAL", "LREAL", "DATE", "DT"))
"""The IEC types whose write check is the same for every vendor (`check_iec`)."""


def iec_kinds(types: Collection[str], **kinds: ValueKind) -> dict[str, ValueKind]:
    """Return the kind of each of a vendor's types: the IEC kind unless `kinds` names another."""
    return {name: kinds[name] if name in kinds else IEC_KINDS[name] for name in types}


def integer_range(bits: int, *, signed: bool) -> tuple[int, int]:
    """Return the inclusive range of a two's complement or unsigned integer of `bits` bits."""
    if signed:
        return -(1 << (bits - 1)), (1 << (bits - 1)) - 1
    return 0, (1 << bits) - 1


def check_integer(value: Value, low: int, high: int, what: str = "value") -> int:
    """Return value as an int within [low, high]; refuse fractions, bools-as-text and overflow."""
    if isinstance(value, bool):
        number = int(value)
    elif isinstance(value, int):
        number = value
    elif isinstance(value, float) and value.is_integer():
        number = int(value)
    elif isinstance(value, str) and _WHOLE.fullmatch(value.strip()):
        number = int(value.strip())
    else:
        raise PlcValueError(f"{what} must be a whole number, not {value!r}")
    if not low <= number <= high:
        raise PlcValueError(f"{what} {number} is outside {low}..{high}")
    return number


_WHOLE = re.compile(r"[+-]?[0-9]{1,40}")
"""ASCII digits only (str.isdigit() also takes "²"), and few enough that int() never refuses."""


def check_float(value: Value, *, single: bool = True, what: str = "value") -> float:
    """Return value as a finite float that fits a REAL (single) or LREAL."""
    if isinstance(value, bool) or not isinstance(value, int | float | str):
        raise PlcValueError(f"{what} must be a number, not {value!r}")
    try:
        number = float(value)
    except ValueError as err:
        raise PlcValueError(f"{what} must be a number, not {value!r}") from err
    except OverflowError as err:  # an int beyond any float, e.g. 10**400
        raise PlcValueError(f"{what} is too large for a {'REAL' if single else 'LREAL'}") from err
    if not math.isfinite(number) or (single and abs(number) > REAL_MAX):
        raise PlcValueError(f"{what} {value!r} does not fit a {'REAL' if single else 'LREAL'}")
    return number


def shortest_real(value: float) -> float:
    """Return the shortest decimal that is the same 32-bit float as value (21.3, not 21.2999...).

    A REAL read back, or printed by a PLC with six decimals ("22.299999"), shows as typed.
    """
    if not math.isfinite(value) or abs(value) > REAL_MAX:
        return value
    packed = struct.pack("<f", value)
    single = float(struct.unpack("<f", packed)[0])
    for digits in range(6, 10):
        short = float(f"{single:.{digits}g}")
        if struct.pack("<f", short) == packed:
            return short
    return single  # not reached: nine digits always name a 32-bit float


def as_single(value: float) -> float | None:
    """Return a float as the 32-bit float a REAL stores; None when no REAL holds it."""
    try:
        return float(struct.unpack("<f", struct.pack("<f", value))[0])
    except OverflowError:
        return None


def check_bool(value: Value, what: str = "value") -> bool:
    """Return value as a bool; accept 0/1 and the usual words."""
    if isinstance(value, bool):
        return value
    if isinstance(value, int | float) and value in (0, 1):
        return bool(value)
    if isinstance(value, str) and value.strip().lower() in _BOOL_WORDS:
        return _BOOL_WORDS[value.strip().lower()]
    raise PlcValueError(f"{what} must be true or false, not {value!r}")


_BOOL_WORDS = {"1": True, "true": True, "on": True, "0": False, "false": False, "off": False}


def check_ascii(value: Value, max_length: int, what: str = "value") -> str:
    """Return value as ASCII text (control characters included) of at most max_length."""
    if not isinstance(value, str):
        raise PlcValueError(f"{what} must be text, not {value!r}")
    if not value.isascii():
        raise PlcValueError(f"{what} may contain ASCII characters only")
    if len(value) > max_length:
        raise PlcValueError(f"{what} is longer than {max_length} characters")
    return value


def check_text(
    value: Value,
    max_length: int,
    what: str = "value",
    *,
    kind: str = "STRING",
    encoding: str = "ascii",
    hint: str = "",
) -> str:
    """Return text of at most max_length characters that `encoding` can write.

    "ascii" and "latin-1" for one byte a character, "utf-16" for a WSTRING (it refuses a lone
    surrogate); `hint` is added to the refusal of a character.
    """
    if not isinstance(value, str):
        raise PlcValueError(f"{what} takes text, not {value!r}")
    try:
        value.encode(encoding)
    except UnicodeEncodeError as err:
        name = _CHARSETS.get(encoding, encoding)
        char = value[err.start]
        raise PlcValueError(
            f"{what}: a {kind} takes {name} text only; {char!r} is not {name}{hint}"
        ) from None
    if len(value) > max_length:
        raise PlcValueError(
            f"{what}: a {kind} holds at most {max_length} characters; the text is longer"
        )
    return value


_CHARSETS = {"ascii": "ASCII", "latin-1": "Latin-1", "utf-16": "UTF-16"}


def decode_error(kind: str, raw: object, what: str) -> PlcProtocolError:
    """Return the error of a JSON value that is no `kind`: a structure or array says so."""
    if isinstance(raw, dict | list):
        shape = "a structure" if isinstance(raw, dict) else "an array"
        return PlcProtocolError(f"{what} is {shape}, not a {kind}; choose one of its members")
    return PlcProtocolError(f"{what}: the PLC sent {str(raw)[:40]!r}, which is no {kind}")


def plain_decimal(value: float) -> str:
    """Format a float as a plain decimal, never in exponent form (1e-05 -> 0.00001)."""
    if value.is_integer() and abs(value) < 1e16:
        return str(int(value)) if value else "0"
    text = format(Decimal(repr(value)), "f")
    return text.rstrip("0").rstrip(".") if "." in text else text


def local_time(value: datetime, zone: tzinfo) -> datetime:
    """Return an aware time in the PLC's zone (a naive one as is); refuse one beyond years 1-9999.

    astimezone raises OverflowError for, say, 0001-01-01 at +05:00: a value error here.
    """
    if value.tzinfo is None:
        return value
    try:
        return value.astimezone(zone)
    except OverflowError as err:
        raise PlcValueError(f"{value.isoformat()} has no time in the PLC's time zone") from err


def type_name(text: str, known: Collection[str], aliases: Mapping[str, str]) -> str:
    """Return a vendor's canonical type name for a typed one; raise PlcAddressError if unknown."""
    name = text.strip().upper()
    name = aliases.get(name, name)
    if name not in known:
        raise PlcAddressError(f"unknown data type {text!r}; use one of {', '.join(known)}")
    return name


def check_moment(kind: str, value: Value, what: str) -> datetime:
    """Return a DATE or DT as a datetime (naive: the PLC's time) from 1970 on; ISO text accepted."""
    if isinstance(value, str):
        try:
            value = datetime.fromisoformat(value.strip())
        except ValueError:
            raise PlcValueError(f"{what} takes a {kind} as an ISO date, not {value!r}") from None
    if not isinstance(value, datetime):
        raise PlcValueError(f"{what} takes a {kind} (a date and time), not {value!r}")
    if value.year < 1970:
        raise PlcValueError(f"{what}: a {kind} starts on 1970-01-01")
    return value


def check_iec(kind: str, value: Value, what: str) -> Value:
    """Return a value checked for BOOL, an integer type, REAL, LREAL, DATE or DT (`CHECKED`)."""
    if kind == "BOOL":
        return check_bool(value, what)
    if kind in INTEGER_RANGES:
        return check_integer(value, *INTEGER_RANGES[kind], what)
    if kind in ("REAL", "LREAL"):
        return check_float(value, single=kind == "REAL", what=what)
    if kind in ("DATE", "DT"):
        return check_moment(kind, value, what)
    raise PlcValueError(f"{what}: a {kind} has no common check")


CLOCK_VARIABLE = "clock_variable"
"""The option naming a DT variable the PLC program copies into its clock (TecoApi, PLCnext)."""


def clock_option(
    options: Mapping[str, object], spell: Callable[[str], str]
) -> dict[str, str | int | bool]:
    """Return the clock variable option as `spell` normalizes its path (none when empty).

    Raise PlcValueError with a form-ready message when it is no valid path.
    """
    clock = options.get(CLOCK_VARIABLE) or ""
    if not isinstance(clock, str):
        raise PlcValueError(f"the clock variable is a variable path, not {clock!r}")
    if not clock.strip():
        return {}
    try:
        return {CLOCK_VARIABLE: spell(clock)}
    except PlcAddressError as err:
        raise PlcValueError(f"clock variable: {err}") from None
