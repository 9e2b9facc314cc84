"""Conversions of one point between what the PLC holds and what Home Assistant shows.

They belong to the point, whatever entity shows it. Every key is optional in the point's
stored data; a point stored before they existed loads unchanged:

- `scale`, `offset`: shown = raw × scale + offset (written values go back the same way).
- `raw_min`, `raw_max`, `shown_min`, `shown_max`: a linear range raw ↔ shown (`0..27648` →
  `0..100`) that takes the place of scale and offset; a read is clamped to the shown range, a
  write outside it is refused before anything is sent.
- `precision`: the decimal places shown, and kept when a shown value is converted back.
- `value_map`: text `0=Off;1=Auto;2=Manual` (raw integer `=` label, pairs split by `;`),
  stored as the user typed it once normalized: the same text as the import/export cell.
- `bits`: an alarm or status word's named bits, in the same form (`0=Overheat;3=Low water`).
- `invert`, `on_value`, `off_value`: what on and off are for a true/false entity (a normally
  closed contact; codes other than 1 and 0).
"""

from __future__ import annotations

from collections.abc import Collection, Mapping
from dataclasses import dataclass
from decimal import Decimal
from functools import lru_cache
import logging
from typing import Any

from homeassistant.exceptions import ServiceValidationError

from ..const import (
    CONF_INVERT,
    CONF_OFF_VALUE,
    CONF_OFFSET,
    CONF_ON_VALUE,
    CONF_PRECISION,
    CONF_RAW_MAX,
    CONF_RAW_MIN,
    CONF_SCALE,
    CONF_SHOWN_MAX,
    CONF_SHOWN_MIN,
    CONF_VALUE_MAP,
    DOMAIN,
)
from ..plc import Value

type Pairs = tuple[tuple[int, str], ...]
"""Raw values (or bit numbers) and their labels, in the order the user gave them."""
LINEAR_KEYS = (CONF_RAW_MIN, CONF_RAW_MAX, CONF_SHOWN_MIN, CONF_SHOWN_MAX)


class InvalidPairs(Exception):
    """A value map or bit list that cannot be read; `key` is the form's error key."""

    def __init__(self, key: str, text: str = "") -> None:
        """Keep the error key and the part of the text at fault."""
        super().__init__(key)
        self.key = key
        self.text = text


def pair_parts(text: str) -> list[tuple[str, str, str]]:
    """Return the parts of a map's text (`;` or lines apart) as (part, left, right), stripped.

    Raise InvalidPairs for a part without `=` and for a text without parts.
    """
    parts = []
    for part in text.replace("\n", ";").split(";"):
        if part.strip():
            left, sep, right = part.partition("=")
            if not sep:
                raise InvalidPairs("map_not_a_pair", part.strip())
            parts.append((part.strip(), left.strip(), right.strip()))
    if not parts:
        raise InvalidPairs("map_empty")
    return parts


def parse_pairs(text: str, *, low: int | None = None, high: int | None = None) -> Pairs:
    """Return `0=Off;1=Auto` as pairs; raise InvalidPairs for a bad, repeated or empty pair."""
    pairs: list[tuple[int, str]] = []
    for part, raw, label in pair_parts(text):
        try:
            number = int(raw, 0)
        except ValueError:
            raise InvalidPairs("map_not_a_pair", part) from None
        if not label:
            raise InvalidPairs("map_not_a_pair", part)
        if (low is not None and number < low) or (high is not None and number > high):
            raise InvalidPairs("map_out_of_range", part)
        if any(number == key or label == name for key, name in pairs):
            raise InvalidPairs("map_repeated", part)
        pairs.append((number, label))
    return tuple(pairs)


def format_pairs(pairs: Pairs) -> str:
    """Return pairs in their stored and exported form, `0=Off;1=Auto`."""
    return ";".join(f"{key}={label}" for key, label in pairs)


def spelled_as_states(text: str, states: Collection[str]) -> str:
    """Return a map's text with each label naming a state in another case spelled as the state.

    `0=Closed;2=OPEN` gives `0=closed;2=open`; a text that cannot be read is returned as it is
    (its check names the fault).
    """
    try:
        pairs = parse_pairs(text)
    except InvalidPairs:
        return text
    spelled = {state.casefold(): state for state in states}
    return format_pairs(tuple((key, spelled.get(label.casefold(), label)) for key, label in pairs))


def stored_pairs(data: Mapping[str, Any], key: str) -> Pairs:
    """Return the pairs a point stores under a key, none when absent (the form checked them)."""
    return _stored_text_pairs(str(data[key])) if data.get(key) else ()


@lru_cache(maxsize=4096)
def _stored_text_pairs(text: str) -> Pairs:
    """Return a stored map's pairs, parsed once for every point storing the text (none if bad)."""
    try:
        return parse_pairs(text)
    except InvalidPairs:
        return ()


def scaled(raw: int | float, scale: float, offset: float) -> int | float:
    """Return raw × scale + offset, computed in decimal so 23 × 0.1 shows as 2.3."""
    if scale == 1 and offset == 0:
        return raw
    value = Decimal(repr(raw)) * Decimal(repr(scale)) + Decimal(repr(offset))
    return (
        int(value) if isinstance(raw, int) and value == value.to_integral_value() else float(value)
    )


def _decimal(value: float) -> Decimal:
    """Return a number as the decimal its shortest text spells."""
    return Decimal(repr(float(value)))


@dataclass(frozen=True, slots=True)
class Linear:
    """A linear range: raw_min..raw_max shown as shown_min..shown_max."""

    raw_min: float
    raw_max: float
    shown_min: float
    shown_max: float

    @property
    def bounds(self) -> tuple[float, float]:
        """The smallest and largest value shown (the range may run downwards)."""
        return min(self.shown_min, self.shown_max), max(self.shown_min, self.shown_max)

    def shown(self, raw: float) -> Decimal:
        """Return the shown value of a raw one, clamped to the shown range."""
        ratio = (_decimal(raw) - _decimal(self.raw_min)) / (
            _decimal(self.raw_max) - _decimal(self.raw_min)
        )
        value = _decimal(self.shown_min) + ratio * (
            _decimal(self.shown_max) - _decimal(self.shown_min)
        )
        low, high = self.bounds
        return min(max(value, _decimal(low)), _decimal(high))

    def raw(self, shown: float) -> Decimal:
        """Return the raw value of a shown one (inside the range)."""
        ratio = (_decimal(shown) - _decimal(self.shown_min)) / (
            _decimal(self.shown_max) - _decimal(self.shown_min)
        )
        return _decimal(self.raw_min) + ratio * (_decimal(self.raw_max) - _decimal(self.raw_min))


@dataclass(frozen=True, slots=True, kw_only=True)
class Conversion:
    """What one point's raw value shows as, and how a shown value is written back."""

    scale: float = 1.0
    offset: float = 0.0
    linear: Linear | None = None
    precision: int | None = None
    value_map: Pairs = ()
    invert: bool = False
    on_value: float | None = None
    off_value: float | None = None

    @property
    def bounds(self) -> tuple[float, float] | None:
        """The range of shown values a linear range allows, if it has one."""
        return self.linear.bounds if self.linear else None

    def shown(self, raw: int | float) -> int | float:
        """Return the shown value of a raw number."""
        if self.linear is None:
            value = scaled(raw, self.scale, self.offset)
            return value if self.precision is None else round(value, self.precision)
        exact = self.linear.shown(raw)
        if self.precision is not None:
            exact = round(exact, self.precision)
        whole = self.precision == 0 or (self.precision is None and isinstance(raw, int))
        if whole and exact == exact.to_integral_value():
            return int(exact)
        return float(exact)

    def raw(self, shown: float, *, integer: bool) -> int | float:
        """Return the raw value to write for a shown one; refuse one outside the linear range."""
        if self.precision is not None:
            shown = round(shown, self.precision)
        if self.linear is not None:
            low, high = self.linear.bounds
            if not low <= shown <= high:
                raise ServiceValidationError(
                    translation_domain=DOMAIN,
                    translation_key="out_of_range",
                    translation_placeholders={
                        "value": f"{shown:g}",
                        "min": f"{low:g}",
                        "max": f"{high:g}",
                    },
                )
            exact = self.linear.raw(shown)
        else:
            exact = (_decimal(shown) - _decimal(self.offset)) / _decimal(self.scale or 1.0)
        return round(exact) if integer else float(exact)

    def label(self, raw: Value | None) -> str | None:
        """Return the label of a raw value, None where the map has none."""
        if isinstance(raw, bool) or not isinstance(raw, int | float):
            return None
        return next((label for key, label in self.value_map if key == raw), None)

    def code(self, label: str) -> int:
        """Return the raw value of a label of the map."""
        for key, name in self.value_map:
            if name == label:
                return key
        raise ServiceValidationError(
            translation_domain=DOMAIN,
            translation_key="not_in_map",
            translation_placeholders={"value": label},
        )

    def is_on(self, raw: Value | None) -> bool | None:
        """Return whether a raw value means on (codes and invert applied), None if neither."""
        if not isinstance(raw, bool | int | float):
            return None
        if self.on_value is not None:
            if raw != self.on_value and self.off_value is not None and raw != self.off_value:
                return None
            on = raw == self.on_value
        elif self.off_value is not None:
            on = raw != self.off_value
        else:
            on = bool(raw)
        return on != self.invert

    def state_value(self, on: bool, *, boolean: bool) -> bool | int | float:
        """Return the raw value to write for on or off (invert applied; a BOOL point as such)."""
        level = on != self.invert
        code = self.on_value if level else self.off_value
        if boolean or code is None:
            return level if boolean else int(level)
        return int(code) if float(code).is_integer() else code


@lru_cache(maxsize=4096)
def shared(conversion: Conversion) -> Conversion:
    """Return the one conversion kept for all equal to this one (most points share a few)."""
    return conversion


def conversion_of(data: Mapping[str, Any]) -> Conversion:
    """Return the conversion a point's stored data describes (older points: scale and offset).

    Points with equal settings get one object.
    """
    linear = None
    if all(data.get(key) is not None for key in LINEAR_KEYS):
        linear = Linear(*(float(data[key]) for key in LINEAR_KEYS))
        if linear.raw_min == linear.raw_max or linear.shown_min == linear.shown_max:
            linear = None
    precision = data.get(CONF_PRECISION)
    return shared(
        Conversion(
            scale=float(data.get(CONF_SCALE, 1.0)),
            offset=float(data.get(CONF_OFFSET, 0.0)),
            linear=linear,
            precision=None if precision is None else int(precision),
            value_map=stored_pairs(data, CONF_VALUE_MAP),
            invert=bool(data.get(CONF_INVERT, False)),
            on_value=None if data.get(CONF_ON_VALUE) is None else float(data[CONF_ON_VALUE]),
            off_value=None if data.get(CONF_OFF_VALUE) is None else float(data[CONF_OFF_VALUE]),
        )
    )


@lru_cache(maxsize=1024)
def labels(value_map: Pairs) -> list[str]:
    """Return a value map's labels in order: one list for every point of an equal map.

    Home Assistant only reads an entity's options; entities of equal maps share them.
    """
    return [label for _, label in value_map]


def check_unmapped(
    logger: logging.Logger, name: str, conversion: Conversion, raw: Value | None, logged: bool
) -> bool:
    """Note a poll's raw value; return whether a value outside the map is logged now.

    Logged once, and again once the value was in the map and left; None (a failed read)
    changes nothing. The entity keeps the flag: no object per entity for it.
    """
    if raw is None:
        return logged
    if conversion.label(raw) is not None:
        return False
    if not logged:
        logger.warning(
            "%s: the PLC holds %s, which its value map does not name; shown as unknown", name, raw
        )
    return True
