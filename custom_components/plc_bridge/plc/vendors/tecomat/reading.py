"""What GetObject requests gave: values and errors by path, and the variables found unknown."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from ...errors import PlcAddressError, PlcError
from .paths import VariablePath


@dataclass(frozen=True, slots=True)
class Gone:
    """A variable the PLC does not know (400.005): its path, and the name the PLC's answer gave."""

    path: VariablePath
    name: str

    def error(self, path: VariablePath) -> PlcAddressError:
        """Return the error of a path that is or lies inside this variable."""
        return PlcAddressError(
            f"{path.text}: the PLC does not know this variable "
            f"(400.005: '{self.name}' is not found)"
        )


@dataclass(slots=True)
class Reading:
    """What GetObject requests gave: raw values and per-path errors, by path key."""

    found: dict[str, Any] = field(default_factory=dict)
    failed: dict[str, PlcError] = field(default_factory=dict)
    gone: dict[str, Gone] = field(default_factory=dict)  # unknown variables (400.005), by key
    too_big: set[str] = field(default_factory=set)  # alone, more items than one answer holds

    def merge(self, other: Reading) -> None:
        """Take in another reading's results."""
        self.found.update(other.found)
        self.failed.update(other.failed)
        self.gone.update(other.gone)
        self.too_big |= other.too_big


def gone_for(path: VariablePath, gone: dict[str, Gone]) -> Gone | None:
    """Return the unknown variable a path is or lies inside."""
    for entry in gone.values():
        if under(path, entry.path):
            return entry
    return None


def under(path: VariablePath, prefix: VariablePath) -> bool:
    """True when path is prefix or lies inside it (compared as the PLC does, ignoring case)."""
    return path.key == prefix.key or path.key.startswith((prefix.key + ".", prefix.key + "["))
