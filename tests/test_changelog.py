"""The changelog names the release the manifest carries, and says what a user must do in it."""

from __future__ import annotations

import json
from pathlib import Path
import re

ROOT = Path(__file__).resolve().parent.parent
MANIFEST = ROOT / "custom_components" / "plc_bridge" / "manifest.json"
RELEASE = re.compile(r"^## (\d+\.\d+\.\d+) \((\d{4}-\d{2}-\d{2})\)$", re.MULTILINE)


def releases() -> list[str]:
    """Return the releases CHANGELOG.md describes, the newest first."""
    return [match[1] for match in RELEASE.finditer((ROOT / "CHANGELOG.md").read_text())]


def test_newest_release_is_the_manifests() -> None:
    """The version Home Assistant and HACS show is the changelog's newest release."""
    version = json.loads(MANIFEST.read_text())["version"]
    assert releases()[:1] == [version]


def test_each_release_says_what_to_do() -> None:
    """Every release has a "What you must do" section, before its first other section."""
    text = (ROOT / "CHANGELOG.md").read_text()
    for part in RELEASE.split(text)[3::3]:
        assert part.lstrip().startswith("### What you must do"), part[:200]
