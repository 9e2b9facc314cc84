"""Tests of a point's conversions: value maps, linear ranges, on/off codes and invert."""

from __future__ import annotations

from homeassistant.exceptions import ServiceValidationError
import pytest

from custom_components.plc_bridge.model.conversion import (
    Conversion,
    InvalidPairs,
    Linear,
    conversion_of,
    format_pairs,
    parse_pairs,
)


def test_value_map_text_round_trips() -> None:
    pairs = parse_pairs(" 0 = Off ; 1=Auto;\n0x2=Manual ")
    assert pairs == ((0, "Off"), (1, "Auto"), (2, "Manual"))
    assert format_pairs(pairs) == "0=Off;1=Auto;2=Manual"


@pytest.mark.parametrize(
    ("text", "key"),
    [
        ("", "map_empty"),
        ("0=Off;Auto", "map_not_a_pair"),
        ("x=Off", "map_not_a_pair"),
        ("0=", "map_not_a_pair"),
        ("0=Off;0=On", "map_repeated"),
        ("0=Off;1=Off", "map_repeated"),
        ("64=Bit", "map_out_of_range"),
    ],
)
def test_bad_value_maps(text: str, key: str) -> None:
    with pytest.raises(InvalidPairs) as err:
        parse_pairs(text, low=0, high=63)
    assert err.value.key == key


def test_linear_range_both_ways() -> None:
    """0..27648 shows as 0..100 %: clamped on read, refused outside the range on write."""
    conversion = Conversion(linear=Linear(0, 27648, 0, 100), precision=1)
    assert conversion.shown(13824) == 50
    assert conversion.shown(1000) == 3.6
    assert conversion.shown(30000) == 100
    assert conversion.shown(-5) == 0
    assert conversion.raw(25, integer=True) == 6912
    assert conversion.raw(3.62, integer=True) == conversion.raw(3.6, integer=True) == 995
    with pytest.raises(ServiceValidationError) as err:
        conversion.raw(100.5, integer=True)
    assert err.value.translation_key == "out_of_range"
    assert err.value.translation_placeholders == {"value": "100.5", "min": "0", "max": "100"}


def test_downward_range() -> None:
    conversion = Conversion(linear=Linear(0, 1000, 100, 0))
    assert conversion.shown(250) == 75
    assert conversion.raw(75, integer=False) == 250.0


def test_stored_points_load_unchanged() -> None:
    """A point stored before conversions existed: scale and offset only."""
    conversion = conversion_of({"scale": 0.5, "offset": 10.0})
    assert conversion == Conversion(scale=0.5, offset=10.0)
    assert conversion.shown(40) == 30
    assert conversion.raw(30, integer=True) == 40


def test_on_off_codes_and_invert() -> None:
    codes = Conversion(on_value=5, off_value=2)
    assert (codes.is_on(5), codes.is_on(2), codes.is_on(7)) == (True, False, None)
    assert codes.state_value(True, boolean=False) == 5
    assert codes.state_value(False, boolean=False) == 2
    inverted = Conversion(invert=True)
    assert (inverted.is_on(True), inverted.is_on(0)) == (False, True)
    assert inverted.state_value(True, boolean=True) is False
    assert inverted.state_value(True, boolean=False) == 0


def test_labels_and_codes() -> None:
    conversion = conversion_of({"value_map": "0=Off;1=Auto"})
    assert conversion.label(1) == "Auto"
    assert conversion.label(7) is None
    assert conversion.label(True) is None
    assert conversion.code("Off") == 0
    with pytest.raises(ServiceValidationError):
        conversion.code("Manual")
