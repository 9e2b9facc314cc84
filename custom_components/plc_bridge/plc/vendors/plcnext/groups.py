"""PLCnext groups: what the PLC registered, and the paths a registration names."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from .paths import VariablePath


@dataclass(frozen=True, slots=True)
class Group:
    """A group the PLC registered: its id, the paths in its order, the program it was made for.

    `created`: registered by this client (201), not an identical one reused (200), which
    another client may be reading: only a created group is unregistered.
    """

    id: str
    paths: tuple[VariablePath, ...]
    crc: Any
    created: bool = False
    names: list[str] = field(default_factory=list)  # as registered: what its answers name


GROUP_IDLE = 120.0
"""Seconds a group may sit unused before the PLC unregisters it (Groups page: "a timeout
period (e.g. 120 seconds) where it will automatically unregister the group")."""
GROUPS_KEPT = 4
"""Groups kept registered for the point sets polls alternate between (poll classes: fast;
fast and normal; fast and slow; all), so that each is one group read, not a new registration."""


def registered(paths: Sequence[VariablePath]) -> tuple[str, list[str]]:
    """Return the `pathPrefix` and the paths a group is registered with.

    Paths of one component go relative to it (the Groups page's example): the PLC then
    answers every read with the short paths.
    """
    components = {path.component for path in paths}
    prefix = f"{components.pop()}/" if len(components) == 1 else ""
    return prefix, [path.name if prefix else path.text for path in paths]
