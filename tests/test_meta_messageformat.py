"""Every text of every language parses as the ICU message format the frontend reads it in.

The frontend formats each string with intl-messageformat: a literal `{` (a JSON example) is taken
for a placeholder and the form shows "Translation error: MALFORMED_ARGUMENT". A literal brace is
written quoted, `'{…}'`; a placeholder is a plain `{name}` (Home Assistant passes strings only).
"""

from __future__ import annotations

import json
from pathlib import Path
import re
from typing import Any

from pyicumessageformat import Parser
import pytest

INTEGRATION = Path(__file__).resolve().parent.parent / "custom_components" / "plc_bridge"
STRINGS: dict[str, Any] = json.loads((INTEGRATION / "strings.json").read_text(encoding="utf-8"))
PARSERS = {"tags ignored": Parser({"allow_tags": False}), "tags read": Parser({"allow_tags": True})}
QUOTED = re.compile(r"'([{}][^']*)'")


def leaves(value: Any, path: str = "") -> list[tuple[str, str]]:
    """Return (path, text) of every string of a JSON tree."""
    if isinstance(value, dict):
        return [leaf for key, item in value.items() for leaf in leaves(item, f"{path}.{key}")]
    return [(path, value)] if isinstance(value, str) else []


TRANSLATIONS = sorted((INTEGRATION / "translations").glob("*.json"))
LANGUAGES = {"strings.json": leaves(STRINGS)} | {
    path.name: leaves(json.loads(path.read_text(encoding="utf-8")))
    for path in TRANSLATIONS
    if path.stem != "en"  # the same as strings.json (test_meta.py)
}
"""Every text of strings.json and of each translation, by file."""


def render(nodes: list[Any]) -> str:
    """Return the text a parsed message shows, with each placeholder written `{name}`."""
    return "".join(node if isinstance(node, str) else f"{{{node['name']}}}" for node in nodes)


def problem(text: str, mode: str) -> str | None:
    """Return why a text is no message the frontend shows as written, None when it is one."""
    try:
        nodes = PARSERS[mode].parse(text)
    except SyntaxError as err:
        return str(err)
    placeholders = [node for node in nodes if not isinstance(node, str)]
    if not all(set(node) == {"name"} for node in placeholders):
        return f"a formatted argument: {placeholders}"
    if not all(re.fullmatch(r"[a-z_][a-z0-9_]*", node["name"]) for node in placeholders):
        return f"a placeholder that is not a plain name: {placeholders}"
    if render(nodes) != QUOTED.sub(r"\1", text).replace("''", "'"):
        return "text quoted by accident (an apostrophe before a brace?)"
    return None


@pytest.mark.parametrize("mode", PARSERS)
@pytest.mark.parametrize("name", LANGUAGES)
def test_every_text_is_a_message(name: str, mode: str) -> None:
    """Each text parses; its placeholders are plain names; no text is quoted by accident."""
    found = [
        f"{path}: {why}"
        for path, text in LANGUAGES[name]
        if (why := problem(text, mode)) is not None
    ]
    assert not found, "\n".join(found)


@pytest.mark.parametrize(
    "text",
    ['for example `[{"address": "VW100"}]`', "{count, plural, one {# point} other {# points}}"],
)
def test_checks_catch_what_the_frontend_refuses(text: str) -> None:
    """A JSON example unquoted fails to parse, and a formatted argument is not a plain name."""
    try:
        nodes = PARSERS["tags ignored"].parse(text)
    except SyntaxError:
        return
    assert any(set(node) != {"name"} for node in nodes if not isinstance(node, str))
