"""A pulse's duration as a point stores it (buttons and commands; outputs.py times it)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from .const import CONF_PULSE, PULSE_MAX, PULSE_MIN


def pulse_seconds(data: Mapping[str, Any]) -> float:
    """Return a point's pulse in seconds, kept within 0.1-60; 0 for a single write."""
    pulse = float(data.get(CONF_PULSE) or 0.0)
    return min(max(pulse, PULSE_MIN), PULSE_MAX) if pulse else 0.0
