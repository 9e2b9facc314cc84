"""The PLCnext simulator's demo project: every elementary type, structures, arrays, bench values."""

from __future__ import annotations

from typing import Any

from .program import PREFIX, Array, Leaf, Node, Program, Variable

MACHINES = {
    "water": "HomeInstance.Boiler.Water",
    "target": "HomeInstance.Boiler.Target",
    "hvac": "HomeInstance.Boiler.Hvac",
    "mode": "HomeInstance.Boiler.Mode",
    "alarms": "HomeInstance.Boiler.Alarms",
    "open": "HomeInstance.Shutter.Open",
    "close": "HomeInstance.Shutter.Close",
    "opened": "HomeInstance.Shutter.Opened",
    "closed": "HomeInstance.Shutter.Closed",
    "running": "HomeInstance.Pump.Running",
    "run": "HomeInstance.Pump.Run",
    "start": "HomeInstance.Pump.Start",
}
"""The demo machines' members by role, a structure each (simulators/machines.py moves them)."""


def default_program(bench: int = 0) -> Program:
    """Return the demo project: every elementary type, a structure, an array, bench values.

    A second program instance, `HomeInstance`, holds the demo's machines (`MACHINES`).
    """
    main = PREFIX + "MainInstance."
    leaves: dict[str, tuple[str, Any, bool]] = {
        "Temperature": ("REAL", 21.5, True),
        "Setpoint": ("REAL", 22.0, False),
        "Pump": ("BOOL", False, False),
        "Alarm": ("BOOL", True, True),
        "Counter": ("DINT", 799244562, True),
        "Speed": ("INT", -1200, False),
        "Small": ("SINT", -5, False),
        "Tiny": ("USINT", 200, False),
        "Mask": ("BYTE", 0x5A, False),
        "Status": ("WORD", 0xBEEF, False),
        "Wide": ("UINT", 60000, False),
        "Flags": ("DWORD", 0xDEADBEEF, False),
        "Energy": ("UDINT", 4_000_000_000, False),
        "Total": ("LINT", -(2**40), False),
        "Big": ("ULINT", 2**63, False),
        "Pattern": ("LWORD", 2**60, False),
        "Precise": ("LREAL", 123456.789, False),
        "Message": ("STRING", "Hello PLCnext", False),
        "Label": ("WSTRING", "Grüße ✓", False),
        "Runtime": ("TIME", 90_000, False),
        "Uptime": ("LTIME", 5_000_000_000, True),
        "Clock": ("DT", "2026-11-26T08:00:00.000Z", False),
        "Today": ("DATE", "2026-11-26", False),
    }
    variables = {
        main + name: Variable(kind, Leaf(kind, value), read_only)
        for name, (kind, value, read_only) in leaves.items()
    }
    steps: list[Node] = [Leaf("DINT", seconds) for seconds in (60, 300, 45)]
    variables[main + "Recipe"] = Variable(
        "RecipeType",
        {
            "Name": Leaf("STRING", "Bread"),
            "Weight": Leaf("REAL", 2.5),
            "Ready": Leaf("BOOL", False),
            "Steps": Array("StepArray", "DINT", ((1, 3),), steps),
        },
    )
    levels: list[Node] = [Leaf("INT", level) for level in (10, 20, 30, 40)]
    variables[main + "Levels"] = Variable(
        "LevelArray", Array("LevelArray", "INT", ((1, 4),), levels)
    )
    rows: list[Node] = [
        Array("ShiftArray", "UINT", ((0, 2),), [Leaf("UINT", row * 10 + shift) for shift in (0, 1)])
        for row in (1, 2, 3)
    ]
    variables[main + "Shifts"] = Variable(
        "WeekArray", Array("WeekArray", "ShiftArray", ((5, 3),), rows)
    )
    grid = [[Leaf("INT", row * 10 + col) for col in (1, 2)] for row in (0, 1)]
    variables[main + "Grid"] = Variable(
        "GridArray", Array("GridArray", "INT", ((0, 2), (1, 2)), grid)
    )
    variables[PREFIX + "GlobalFlag"] = Variable("BOOL", Leaf("BOOL", True))
    variables |= _machines()
    for index in range(bench):
        variables[f"{PREFIX}Bench.Value{index}"] = Variable("DINT", Leaf("DINT", index), True)
    return Program(variables)


def _machines() -> dict[str, Variable]:
    """Return the demo machines' structures: the boiler's words (INT), the others' bits."""
    members: dict[str, dict[str, Node]] = {}
    for role, path in MACHINES.items():
        machine, member = path.rsplit(".", 1)
        leaf = Leaf("INT", 550 if role == "water" else 0) if "Boiler" in machine else None
        members.setdefault(machine, {})[member] = leaf or Leaf("BOOL", False)
    return {
        PREFIX + machine: Variable(machine.split(".")[1] + "Type", node)
        for machine, node in members.items()
    }
