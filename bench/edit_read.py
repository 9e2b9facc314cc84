"""Import benchmark: points added to a paced S7-200 SMART, and when their values are shown.

`python -m bench.edit_read [--points 1000] [--pacing 1.0]` runs bench/test_edit_read.py in Home
Assistant's test harness (in this process's Python, real time): a save adds the points to a
PLC polled at its pacing. It prints one paced read of those points, the time from the save until
every new entity shows its value (target: within one paced read and the edit pause), and how
long after its request's reply each value is shown (target: about a second at most).
"""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path
import shlex
import subprocess
import sys
from typing import Any

from custom_components.plc_bridge.runtime.polling import EDIT_DELAY

ROOT = Path(__file__).resolve().parent.parent
LAG_TARGET = 1.0
"""Seconds after its request's reply a value may be shown."""


def run(points: int, pacing: float) -> dict[str, Any] | str:
    """Run the Home Assistant part; its figures, or the tail of its output when it failed."""
    env = os.environ | {"BENCH_EDIT_POINTS": str(points), "BENCH_EDIT_PACING": str(pacing)}
    command = [sys.executable, "-m", "pytest", "bench/test_edit_read.py", "-q", "-s"]
    command += ["-p", "no:cacheprovider"]
    done = subprocess.run(command, cwd=ROOT, env=env, capture_output=True, text=True, check=False)
    for line in done.stdout.splitlines():
        if line.startswith("BENCH "):
            result: dict[str, Any] = json.loads(line.removeprefix("BENCH "))
            result["passed"] = done.returncode == 0
            return result
    return done.stdout[-2000:] + done.stderr[-2000:]


def targets_met(result: dict[str, Any]) -> bool:
    """True when every value came within one paced read of the save, each soon after its reply."""
    all_shown = result["all_shown_s"]
    return (
        all_shown is not None
        and all_shown <= result["paced_read_s"] + EDIT_DELAY + result["pacing_s"]
        and result["max_lag_s"] <= LAG_TARGET
    )


def text(result: dict[str, Any], command: str) -> str:
    """Return the figures as lines, each beside its target."""
    return "\n".join(
        [
            f"$ {command}",
            f"{result['points']} word points imported into an S7-200 SMART of"
            f" {result['kept_points']} (simulator, pacing {result['pacing_s']:g} s,"
            f" {result['requests']} requests a read)",
            f"one paced read of the imported points: {result['paced_read_s']} s",
            f"every imported value shown {result['all_shown_s']} s after the save (target <="
            f" one paced read + the {EDIT_DELAY:g} s edit pause + one request interval);"
            f" the first after {result['first_shown_s']} s",
            f"shown after its request's reply: the first request's {result['first_request_lag_s']}"
            f" s, the slowest {result['max_lag_s']} s (target <= {LAG_TARGET:g} s)",
            f"read requests from the save until all were shown: {result['reads_after_save']}",
            f"targets met: {'yes' if targets_met(result) else 'NO'}",
        ]
    )


def main() -> int:
    """Parse the command line, run, print."""
    parser = argparse.ArgumentParser(prog="python -m bench.edit_read", description=__doc__)
    parser.add_argument("--points", type=int, default=1000, help="points the save adds")
    parser.add_argument("--pacing", type=float, default=1.0, help="s between requests")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    result = run(args.points, args.pacing)
    if isinstance(result, str):
        print(f"the Home Assistant part failed:\n{result}")
        return 1
    if args.json:
        print(json.dumps(result))
    else:
        print(text(result, shlex.join(["python", "-m", "bench.edit_read", *sys.argv[1:]])))
    return 0 if result["passed"] and targets_met(result) else 1


if __name__ == "__main__":
    sys.exit(main())
