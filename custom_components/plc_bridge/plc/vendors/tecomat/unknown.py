"""Variables the PLC said it does not know (400.005): each asked again on its own timer.

A renamed variable would otherwise cost a failed request at every poll. Each unknown variable
(a whole structure, when that is what went) is asked again on its own, first after FIRST_DELAY
(a variable renamed back shows again within a poll or two), then after a delay that doubles
while it stays unknown; a new program (GetInfo's stamp, 3.2) forgets them all at once.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

from ...errors import PlcError
from .paths import VariablePath
from .reading import Gone, gone_for

FIRST_DELAY = 2.0
"""Seconds before a variable found unknown is first asked about again."""
LONGEST_DELAY = 300.0
"""Seconds at most between two questions about a variable still unknown."""


@dataclass(slots=True)
class _Entry:
    """One unknown variable and when to ask about it again."""

    gone: Gone
    due: float
    delay: float


class UnknownVariables:
    """The variables a client found unknown, by key, each with its own back-off timer."""

    def __init__(self) -> None:
        """Start with none."""
        self._entries: dict[str, _Entry] = {}

    def __bool__(self) -> bool:
        """True while any variable is unknown."""
        return bool(self._entries)

    def __contains__(self, key: object) -> bool:
        """True when the variable of this key is unknown."""
        return key in self._entries

    def gone(self) -> dict[str, Gone]:
        """Return the unknown variables by key."""
        return {key: entry.gone for key, entry in self._entries.items()}

    def add(self, gone: Iterable[Gone], now: float, delay: float = FIRST_DELAY) -> None:
        """Remember variables found unknown now; a known one keeps its timer."""
        for entry in gone:
            if entry.path.key not in self._entries:
                self._entries[entry.path.key] = _Entry(entry, now + delay, delay)

    def due(self, now: float) -> list[Gone]:
        """Return the variables whose time to be asked again has come."""
        return [entry.gone for entry in self._entries.values() if entry.due <= now]

    def found(self, key: str) -> None:
        """Forget a variable the PLC knows again."""
        self._entries.pop(key, None)

    def still_gone(self, key: str, now: float) -> None:
        """Ask about a variable still unknown later: twice the last delay, at most LONGEST_DELAY."""
        entry = self._entries[key]
        entry.delay = min(entry.delay * 2, max(LONGEST_DELAY, entry.delay))
        entry.due = now + entry.delay

    def skip(
        self, paths: dict[str, VariablePath]
    ) -> tuple[dict[str, VariablePath], dict[str, PlcError]]:
        """Return the paths to ask, and the errors of those that are or lie inside one unknown."""
        gone = self.gone()
        if not gone:
            return paths, {}
        known: dict[str, VariablePath] = {}
        skipped: dict[str, PlcError] = {}
        for key, path in paths.items():
            if (entry := gone_for(path, gone)) is not None:
                skipped[key] = entry.error(path)
            else:
                known[key] = path
        return known, skipped

    def keep_used(self, paths: Iterable[VariablePath]) -> None:
        """Forget the variables no asked path is or lies inside (their points were removed)."""
        gone = self.gone()
        used = {found.path.key for path in paths if (found := gone_for(path, gone)) is not None}
        self._entries = {key: entry for key, entry in self._entries.items() if key in used}

    def clear(self) -> None:
        """Forget them all (a new program: every name is asked again)."""
        self._entries.clear()
