"""Pure request planning helpers: split a poll into the fewest requests a vendor's limits allow."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from typing import Protocol

from .errors import PlcError
from .types import Point


class Keyed(Protocol):
    """A parsed address that names its variable by a key (as the PLC compares names)."""

    @property
    def key(self) -> str:
        """The variable's name as the PLC compares it."""
        ...


def distinct[K: Keyed](
    points: Iterable[Point], parse: Callable[[str], K], check_type: Callable[[str], object]
) -> dict[str, K]:
    """Return the valid addresses of points, once each by key; an invalid point is left out."""
    found: dict[str, K] = {}
    for point in points:
        try:
            address = parse(point.address)
            check_type(point.data_type)
        except PlcError:
            continue
        found.setdefault(address.key, address)
    return found


def chunks[T](items: Sequence[T], size: int) -> list[Sequence[T]]:
    """Split items into consecutive chunks of at most `size`."""
    return [items[start : start + size] for start in range(0, len(items), size)]


def pack[T](
    items: Iterable[T],
    cost: Callable[[T], int],
    budget: int,
    *,
    base: int = 0,
    max_items: int = 0,
) -> list[list[T]]:
    """Pack items in order into groups whose `base + sum(cost)` stays within `budget`.

    `max_items` (when not 0) also caps the items of a group. An item that does not fit even
    alone gets a group of its own; the caller refuses or reports it.
    """
    groups: list[list[T]] = []
    current: list[T] = []
    used = base
    for item in items:
        weight = cost(item)
        full = max_items and len(current) >= max_items
        if current and (used + weight > budget or full):
            groups.append(current)
            current, used = [], base
        current.append(item)
        used += weight
    if current:
        groups.append(current)
    return groups
