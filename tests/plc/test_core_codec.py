"""Value checks shared by vendors."""

from __future__ import annotations

from datetime import datetime
import math

import pytest

from custom_components.plc_bridge.plc import PlcValueError, Value, ValueKind
from custom_components.plc_bridge.plc.codec import (
    CHECKED,
    INTEGER_RANGES,
    as_single,
    check_ascii,
    check_bool,
    check_float,
    check_iec,
    check_integer,
    check_text,
    decode_error,
    iec_kinds,
    integer_range,
    plain_decimal,
    shortest_real,
)


@pytest.mark.parametrize(
    ("value", "expected"),
    [
        (1e-05, "0.00001"),
        (1.5e20, "150000000000000000000"),
        (0.1, "0.1"),
        (-2.0, "-2"),
        (0.0, "0"),
        (123456.789, "123456.789"),
        (1e16, "10000000000000000"),
        (-3.25e-7, "-0.000000325"),
    ],
)
def test_plain_decimal_never_uses_exponent(value: float, expected: str) -> None:
    assert plain_decimal(value) == expected
    assert "e" not in plain_decimal(value).lower()
    assert float(plain_decimal(value)) == value


@pytest.mark.parametrize(
    ("value", "low", "high", "expected"),
    [(5, 0, 10, 5), (True, 0, 1, 1), (3.0, 0, 10, 3), (" -4 ", -5, 5, -4), ("+7", 0, 9, 7)],
)
def test_check_integer_accepts(value: object, low: int, high: int, expected: int) -> None:
    assert check_integer(value, low, high) == expected  # type: ignore[arg-type]


@pytest.mark.parametrize("value", [256, -1, 1.5, "x", "1.5", [1], "--5", "+-5", "²", "١"])
def test_check_integer_refuses(value: object) -> None:
    with pytest.raises(PlcValueError):
        check_integer(value, *INTEGER_RANGES["BYTE"])  # type: ignore[arg-type]


def test_integer_range() -> None:
    assert integer_range(16, signed=True) == INTEGER_RANGES["INT"]
    assert integer_range(32, signed=False) == INTEGER_RANGES["UDINT"]


def test_check_float() -> None:
    assert check_float("2.5") == 2.5
    assert check_float(3) == 3.0
    assert check_float(1e300, single=False) == 1e300
    for bad in (1e39, float("nan"), float("inf"), True, "abc", [1]):
        with pytest.raises(PlcValueError):
            check_float(bad)  # type: ignore[arg-type]


def test_check_bool() -> None:
    assert check_bool(True) is True
    assert check_bool(0) is False
    assert check_bool(" ON ") is True
    assert check_bool("false") is False
    for bad in (2, "maybe", 0.5):
        with pytest.raises(PlcValueError):
            check_bool(bad)


def test_check_ascii() -> None:
    assert check_ascii("hello", 10) == "hello"
    with pytest.raises(PlcValueError, match="ASCII"):
        check_ascii("Žluťoučký", 20)
    with pytest.raises(PlcValueError, match="longer"):
        check_ascii("x" * 11, 10)
    with pytest.raises(PlcValueError, match="text"):
        check_ascii(5, 10)
    assert check_ascii("line 1\r\nline 2\tend", 30) == "line 1\r\nline 2\tend"


@pytest.mark.parametrize(
    ("value", "shown"),
    [
        (22.299999, 22.3),
        (21.299999237060547, 21.3),
        (0.1, 0.1),
        (1e-05, 1e-05),
        (16777217.0, 16777216.0),
    ],
)
def test_shortest_real(value: float, shown: float) -> None:
    assert shortest_real(value) == shown


def test_shortest_real_passes_what_is_no_real() -> None:
    assert shortest_real(1e300) == 1e300
    assert math.isinf(shortest_real(float("inf")))


@pytest.mark.parametrize(
    ("kind", "value", "expected"),
    [
        ("BOOL", "on", True),
        ("SINT", "-128", -128),
        ("ULINT", 2**64 - 1, 2**64 - 1),
        ("REAL", 3, 3.0),
        ("LREAL", "1e300", 1e300),
        ("DT", "2024-05-06T07:08:09", datetime(2024, 5, 6, 7, 8, 9)),
        ("DATE", datetime(1970, 1, 1), datetime(1970, 1, 1)),
    ],
)
def test_check_iec_accepts(kind: str, value: Value, expected: Value) -> None:
    """The checks PLCnext, TecoApi and S7 share: one function for every IEC elementary type."""
    assert check_iec(kind, value, "x") == expected
    assert kind in CHECKED


@pytest.mark.parametrize(
    ("kind", "value"),
    [("BOOL", 2), ("SINT", 128), ("REAL", 1e39), ("DT", "1969-12-31T23:59:59"), ("TIME", 1)],
)
def test_check_iec_refuses(kind: str, value: Value) -> None:
    """A value out of its type's range, or a type the shared check does not know."""
    with pytest.raises(PlcValueError):
        check_iec(kind, value, "x")


@pytest.mark.parametrize(
    ("encoding", "text", "message"),
    [
        ("ascii", "Žluť", "a STRING takes ASCII text only; 'Ž' is not ASCII"),
        ("latin-1", "ok €", "a STRING takes Latin-1 text only; '€' is not Latin-1"),
        ("utf-16", "a\ud800", "a STRING takes UTF-16 text only; '\\\\ud800' is not UTF-16"),
    ],
)
def test_check_text_refuses_what_the_encoding_cannot_write(
    encoding: str, text: str, message: str
) -> None:
    """One byte a character (ASCII, Latin-1), or UTF-16 with no lone surrogate (a WSTRING)."""
    with pytest.raises(PlcValueError, match=message):
        check_text(text, 10, "x", encoding=encoding)
    assert check_text("Straße ✓", 10, encoding="utf-16") == "Straße ✓"
    with pytest.raises(PlcValueError, match="a WSTRING holds at most 3 characters"):
        check_text("abcd", 3, kind="WSTRING", encoding="utf-16")


def test_decode_error_names_a_structure_or_an_array() -> None:
    """A member-less answer says what it is; any other is quoted, cut at 40 characters."""
    assert "is a structure, not a INT" in str(decode_error("INT", {"a": 1}, "x"))
    assert "is an array, not a INT" in str(decode_error("INT", [1], "x"))
    assert (
        str(decode_error("BOOL", "y" * 99, "x"))
        == f"x: the PLC sent {'y' * 40!r}, which is no BOOL"
    )


def test_iec_kinds_and_as_single() -> None:
    """A vendor's kinds are the IEC ones but where it says otherwise; a REAL's 32-bit float."""
    kinds = iec_kinds(("BOOL", "STRING", "TIME"), TIME=ValueKind.INTEGER)
    assert kinds == {"BOOL": ValueKind.BOOL, "STRING": ValueKind.TEXT, "TIME": ValueKind.INTEGER}
    assert as_single(0.1) == 0.10000000149011612
    assert as_single(1e39) is None
