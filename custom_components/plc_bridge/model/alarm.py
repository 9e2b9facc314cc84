"""Alarm and status words: one integer point whose named bits are each a binary sensor.

The point's own platform is `event` (one event entity fires `raised` / `cleared` with the
bit's name); its `bits` (`0=Overheat;3=Low water`) add a binary sensor per named bit, of
device class problem unless the point names another. All read the one point of the poll.
"""

from __future__ import annotations

from ..plc import Value
from .conversion import Pairs
from .points import PointConfig


def word_bits(config: PointConfig) -> Pairs:
    """Return the named bits of an alarm word point."""
    return config.bit_pairs


def bit_set(raw: Value | None, bit: int) -> bool | None:
    """Return whether a bit of a raw integer is set, None for no integer."""
    if isinstance(raw, bool) or not isinstance(raw, int):
        return None
    return bool(raw >> bit & 1)
