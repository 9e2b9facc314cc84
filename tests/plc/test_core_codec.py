"""Value checks shared by vendors."""

from __future__ import annotations

import math

import pytest

from custom_components.plc_bridge.plc import PlcValueError
from custom_components.plc_bridge.plc.codec import (
    INTEGER_RANGES,
    check_ascii,
    check_bool,
    check_float,
    check_integer,
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
