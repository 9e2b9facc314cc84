"""The Home Assistant part of the poll benchmark: bench/test_*.py run by pytest, shown as text."""

from __future__ import annotations

import json
from pathlib import Path
import subprocess
import sys
from typing import Any

ROOT = Path(__file__).resolve().parent.parent


def ha_checks() -> list[dict[str, Any]] | str:
    """Run the Home Assistant checks (bench/test_*.py); their figures, or why they failed."""
    command = [
        sys.executable,
        "-m",
        "pytest",
        "bench/test_quiet_poll.py",
        "bench/test_setup_time.py",
        "bench/test_machine_kinds.py",
        "bench/test_expose_burst.py",
    ]
    command += ["-q", "-s", "-p", "no:cacheprovider"]
    done = subprocess.run(command, cwd=ROOT, capture_output=True, text=True, check=False)
    results = [
        json.loads(line.removeprefix("BENCH "))
        for line in done.stdout.splitlines()
        if line.startswith("BENCH ")
    ]
    if not results:
        return done.stdout[-2000:] + done.stderr[-2000:]
    for result in results:
        result["passed"] = done.returncode == 0
    return results


def check_text(result: dict[str, Any]) -> str:
    """Return one Home Assistant check as text."""
    if result["check"] == "setup_time":
        return (
            f"setup ({result['vendor']}, {result['points']} points in {result['devices'] - 1}"
            f" devices, in Home Assistant): {result['setup_to_states_ms']} ms from"
            f" async_setup to {result['available']} of {result['states_written']} states"
            f" written and available; {result['devices']} devices;"
            f" {result['requests_first_poll']} requests in the first poll"
        )
    if result["check"] == "machine_kinds":
        count = result["requests_per_poll"]
        requests = f"{count} request" + "s" * (count != 1)
        return (
            f"machine kinds ({result['vendor']}: {result['kinds']} = {result['addresses']}"
            f" addresses, in Home Assistant): {requests} per poll;"
            f" the plan of its {result['addresses']} addresses alone:"
            f" {result['planned_requests']} (target: equal)"
        )
    if result["check"] == "expose_burst":
        count = result["write_requests"]
        extra = result["requests"] - count
        return (
            f"exposes ({result['vendor']}: {result['exposes']} changed at once):"
            f" {count} write request{'s' * (count != 1)} = minimum {result['minimum']}"
            + (f" (+{extra} read-back)" if extra else "")
        )
    return (
        f"quiet poll ({result['vendor']}, {result['points']} sensor points, {result['polls']} polls"
        f" with nothing changed, in Home Assistant): {result['state_changed']} state_changed"
        f" events (target 0), {result['state_writes']} async_write_ha_state calls"
    )
