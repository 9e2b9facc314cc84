"""Module names say what a module holds (STYLE.md, "Names"): no helper, util or manager."""

from __future__ import annotations

from pathlib import Path

import pytest

PACKAGE = Path(__file__).parents[1] / "custom_components" / "plc_bridge"
VAGUE = {"helper", "helpers", "util", "utils", "manager", "managers", "misc", "common"}


@pytest.mark.parametrize(
    "path", sorted(PACKAGE.rglob("*.py")), ids=lambda path: str(path.relative_to(PACKAGE))
)
def test_module_named_for_what_it_holds(path: Path) -> None:
    """A reader finds a behaviour by guessing the file from its name."""
    assert path.stem not in VAGUE
