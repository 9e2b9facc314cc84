"""The demo's machines as a running PLC program moves them, on any simulator's variables.

A boiler whose water (tenths of a degree) drifts and raises Overheat (bit 0 of its alarm word)
above its set point, a shutter whose open and close commands reach their limit switches, and a
pump whose contactor follows its command: what scripts/demo_plcs.py builds entities from.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
import math
from typing import Any

ROLES = (
    *("water", "target", "hvac", "mode", "alarms"),
    *("open", "close", "opened", "closed", "running", "run", "start"),
)
"""The machines' variables, in the order scripts/demo_plcs.py lists their addresses."""


def run_machines(
    elapsed: float,
    get: Callable[[str], Any],
    put: Callable[[str, Any], None],
    at: Mapping[str, str],
) -> None:
    """Move the machines one step: `at` names each role's variable, `get`/`put` reach them."""
    water = round(550 + 50 * math.sin(2 * math.pi * elapsed / 600))
    put(at["water"], water)
    target = int(get(at["target"]))
    put(at["alarms"], int(get(at["alarms"])) & ~1 | int(0 < target < water))
    put(at["running"], bool(get(at["run"])))
    opening, closing = bool(get(at["open"])), bool(get(at["close"]))
    if opening != closing:
        put(at["opened"], opening)
        put(at["closed"], closing)
