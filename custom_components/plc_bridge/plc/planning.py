"""Pure request planning helpers: split a poll into the fewest requests a vendor's limits allow."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence


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
