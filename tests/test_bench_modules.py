"""Every bench module imports and every bench entry point runs on a tiny size: none breaks unseen.

The entry points run as `python -m bench.<name>` in a subprocess, as their users run them.
"""

from __future__ import annotations

import importlib
from pathlib import Path
import pkgutil
import subprocess
import sys

import pytest

import bench

ROOT = Path(__file__).resolve().parent.parent
TIMEOUT = 240
"""Seconds an entry point may take on its tiny size (a loaded machine shares two cores)."""

ENTRY_POINTS: dict[str, tuple[list[str], str]] = {
    "poll": (["--points", "1", "--polls", "1", "--no-ha"], "requests"),
    "poll_classes": (["--points", "10"], "poll classes"),
    "peers": (["--points", "1", "--polls", "1"], "pyPLCn"),
    "s7_libraries": ([], "python-snap7"),
    "plant": (
        ["--minutes", "0", "--plcs", "1", "--points", "10", "--changing", "1", "--pacing", "0"],
        "every entity registered",
    ),
    "edit_read": (["--points", "32", "--pacing", "0.1"], "targets met: yes"),
    "objects": (["--points", "10"], "per point entity"),
    "serve": (["s7_smart", "1"], '"port"'),
    "plant_sims": (["1", "1", "1"], '"port"'),
}
"""Each runnable bench module: its smallest arguments, and what its output must show."""


def modules() -> list[str]:
    """Return the name of every module in bench/."""
    return sorted(info.name for info in pkgutil.iter_modules(bench.__path__))


def runnable(name: str) -> bool:
    """True when the module is meant to run as `python -m bench.<name>`."""
    return 'if __name__ == "__main__":' in (ROOT / "bench" / f"{name}.py").read_text()


@pytest.mark.parametrize("name", modules())
def test_bench_module_imports(name: str) -> None:
    """The module imports (what it imports from the integration and the tests still exists)."""
    importlib.import_module(f"bench.{name}")


def test_every_entry_point_is_run() -> None:
    """A new runnable bench module is added to ENTRY_POINTS, so that it is run below."""
    assert {name for name in modules() if runnable(name)} == set(ENTRY_POINTS)


@pytest.mark.parametrize("name", sorted(ENTRY_POINTS))
def test_bench_entry_point_runs(name: str) -> None:
    """`python -m bench.<name>` on its smallest size ends well and prints its figures."""
    arguments, shown = ENTRY_POINTS[name]
    done = subprocess.run(
        [sys.executable, "-m", f"bench.{name}", *arguments],
        cwd=ROOT,
        input="",  # the serving ones run until their standard input closes
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
        check=False,
    )
    output = done.stdout + done.stderr
    assert done.returncode == 0, output[-3000:]
    assert shown in done.stdout, output[-3000:]
