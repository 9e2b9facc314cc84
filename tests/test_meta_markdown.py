"""No Markdown where the frontend shows a text as it is: a backtick or `**` would show literally.

The frontend renders Markdown (ha-markdown) in a flow step's description, an abort reason and
a repair issue's description; it shows as plain text the titles, field labels, menu and
selector labels, form errors, section names and descriptions, action names, descriptions and
fields, exception messages and entity names. A field's help (`data_description`) goes through
ha-markdown too, but is a line under the field: it is kept plain as well, as the issue asks.
"""

from __future__ import annotations

from collections.abc import Iterator
import json
from pathlib import Path
from typing import Any

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "custom_components" / "plc_bridge"
FILES = [PACKAGE / "strings.json", *sorted((PACKAGE / "translations").glob("*.json"))]
MARKDOWN = ("`", "**")


def texts(node: Any, path: tuple[str, ...] = ()) -> Iterator[tuple[tuple[str, ...], str]]:
    """Yield every text of a strings file with the keys that lead to it."""
    if isinstance(node, dict):
        for key, value in node.items():
            yield from texts(value, (*path, key))
    elif isinstance(node, str):
        yield path, node


def rendered(path: tuple[str, ...]) -> bool:
    """True where the frontend renders the text as Markdown (and Markdown may be used)."""
    step_description = len(path) >= 3 and path[-3] == "step" and path[-1] == "description"
    issue_description = path[0] == "issues" and path[-1] == "description"
    return step_description or issue_description or "abort" in path


@pytest.mark.parametrize("strings", FILES, ids=lambda path: path.name)
def test_no_markdown_where_shown_plain(strings: Path) -> None:
    """Field help, errors, labels, actions and messages hold no backtick and no `**`."""
    found = [
        f"{'.'.join(path)}: {text}"
        for path, text in texts(json.loads(strings.read_text(encoding="utf-8")))
        if not rendered(path) and any(mark in text for mark in MARKDOWN)
    ]
    assert not found, "\n".join(found)


def test_rendered_places_told_apart() -> None:
    """The rule's places: a step's description is Markdown, its field help and errors are not."""
    assert rendered(("config", "step", "user", "description"))
    assert rendered(("config", "abort", "already_configured"))
    assert rendered(("issues", "certificate_changed", "description"))
    assert not rendered(("config", "step", "user", "data_description", "vendor"))
    assert not rendered(("config", "error", "config_tag"))
    assert not rendered(("services", "write", "fields", "points", "description"))
    assert not rendered(("config", "step", "vendor", "sections", "advanced", "description"))
