"""Run a benchmark's Home Assistant part against other code: before and after from one command.

`--against DIR` names a folder holding another revision's `custom_components/`, made outside
the toolchain (it has no git), for instance
`git archive main custom_components | tar -x -C bench/results/main`. The benchmark then runs
once in that folder, every other top-level entry of this tree linked in, and once here.
Delete the folder afterwards: tests that look for every manifest in the tree would find its.
"""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
KEEP = {"custom_components", ".git"}


def tree_with(folder: Path) -> Path:
    """Return `folder` made a tree to run in: its custom_components/, the rest this tree's."""
    folder = folder.resolve()
    if not (folder / "custom_components").is_dir():
        raise SystemExit(f"{folder} holds no custom_components/")
    for entry in ROOT.iterdir():
        link = folder / entry.name
        if entry.name not in KEEP and not link.exists() and not link.is_symlink():
            link.symlink_to(entry)
    return folder
