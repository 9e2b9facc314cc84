"""Print what the demo's Home Assistant needs: PLC Bridge's requirements and those it sets up.

`hass --skip-pip` installs nothing, so everything PLC Bridge (its manifest), the demo's
configuration.yaml and onboarding load must be there beforehand: the manifests' requirements,
with those of their dependencies, after-dependencies and platform domains, resolved recursively
from Home Assistant's own files. (scripts/demo_check.py fails on any integration that still
misses a module.)
"""

from __future__ import annotations

import json
from pathlib import Path

import homeassistant
from homeassistant.const import Platform

PLATFORMS = {platform.value for platform in Platform}

DEMO = ["frontend", "config", "http", "person", "recorder", "history", "logger"]
"""What scripts/develop's configuration.yaml sets up."""
ONBOARDING = [
    "onboarding",
    "analytics",
    "google_translate",
    "met",
    "radio_browser",
    "shopping_list",
]
"""What onboarding sets up (components/onboarding/views.py: the core config step)."""
AROUND = ["assist_pipeline", "assist_satellite", "ai_task", "camera", "infrared", "radio_frequency"]
"""What Home Assistant 2026.11 sets up beside those (read off the demo's log; demo_check.py
fails on a missing module, should this list fall behind a newer release)."""


def requirements(domains: list[str]) -> list[str]:
    """Return the requirements of the domains and of everything they depend on."""
    components = Path(homeassistant.__file__).parent / "components"
    seen: set[str] = set()
    found: dict[str, None] = {}
    todo = list(domains)
    while todo:
        domain = todo.pop()
        manifest_file = components / domain / "manifest.json"
        if domain in seen or not manifest_file.exists():
            continue
        seen.add(domain)
        manifest = json.loads(manifest_file.read_text(encoding="utf-8"))
        found.update(dict.fromkeys(manifest.get("requirements", [])))
        todo += manifest.get("dependencies", []) + manifest.get("after_dependencies", [])
        # An integration's entity platforms (tts.py, todo.py, ...) set their domains up too.
        todo += [path.stem for path in (components / domain).glob("*.py") if path.stem in PLATFORMS]
    return sorted(found)


def own_requirements() -> list[str]:
    """Return PLC Bridge's own requirements (its manifest's: lxml, python-snap7)."""
    manifest = Path(__file__).resolve().parent.parent / "custom_components/plc_bridge/manifest.json"
    return list(json.loads(manifest.read_text(encoding="utf-8"))["requirements"])


if __name__ == "__main__":
    print("\n".join(requirements(DEMO + ONBOARDING + AROUND) + own_requirements()))
