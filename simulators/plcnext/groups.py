"""Registered groups of the PLCnext simulator (the Groups page): ids, paths, idle expiry."""

from __future__ import annotations

from dataclasses import dataclass
import secrets
import time
from typing import Any


@dataclass(slots=True)
class Group:
    """A registered group: its path prefix, its paths in order, and its last use."""

    prefix: str
    paths: list[str]
    used: float


class Groups:
    """The groups the PLC knows; one idle for longer than `timeout` seconds is dropped."""

    def __init__(self, timeout: float = 120.0) -> None:
        """Start with none."""
        self.timeout = timeout
        self.registered: dict[str, Group] = {}

    def __len__(self) -> int:
        """Return how many groups are registered."""
        return len(self.registered)

    def clear(self) -> None:
        """Forget every group (a restart of the web server, a new project)."""
        self.registered.clear()

    def expire(self) -> None:
        """Drop the groups idle for longer than the timeout."""
        now = time.monotonic()
        for group_id, group in list(self.registered.items()):
            if now - group.used > self.timeout:
                del self.registered[group_id]

    def register(self, prefix: str, paths: list[str]) -> tuple[int, str]:
        """Return 200 and the id of an identical group (reused), else 201 and a new id."""
        for group_id, group in self.registered.items():
            if (group.prefix, group.paths) == (prefix, paths):
                group.used = time.monotonic()
                return 200, group_id
        group_id = f"g{secrets.randbelow(9 * 10**9) + 10**9}"
        self.registered[group_id] = Group(prefix, list(paths), time.monotonic())
        return 201, group_id

    def use(self, group_id: str) -> Group | None:
        """Return a group by id, kept alive by the use; None when the PLC does not know it."""
        group = self.registered.get(group_id)
        if group is not None:
            group.used = time.monotonic()
        return group

    def delete(self, group_id: str) -> bool:
        """Unregister a group; False when there was none of that id."""
        return self.registered.pop(group_id, None) is not None

    def report(self) -> list[dict[str, Any]]:
        """Return the Report Groups listing (counts as text, as a real PLC sends them)."""
        return [
            {"id": group_id, "variableCount": str(len(group.paths)), "uri": f"/groups/{group_id}"}
            for group_id, group in self.registered.items()
        ]
