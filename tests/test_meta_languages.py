"""Every translation has every text of strings.json, with the same placeholders, and no more.

A missing text would show in English, a lost placeholder would drop what the message names,
and a text strings.json no longer has is one nobody updates. Field help is shown without
markdown, in every language as in English (test_meta_markdown.py).
"""

from __future__ import annotations

import json
from pathlib import Path
import re
from typing import Any

import pytest

INTEGRATION = Path(__file__).resolve().parent.parent / "custom_components" / "plc_bridge"
STRINGS: dict[str, Any] = json.loads((INTEGRATION / "strings.json").read_text(encoding="utf-8"))
FILES = sorted((INTEGRATION / "translations").glob("*.json"))
PLACEHOLDER = re.compile(r"(?<!')\{(\w+)\}")
LANGUAGES = {"en", "cs", "de", "es", "fr", "it", "nl", "pl", "zh-Hans"}
"""English, and the languages of the families' users (issue 25): Czech (Tecomat), German
(Siemens, Phoenix Contact), Chinese (S7-200 SMART), and those ha-s7plc's users read."""


def leaves(value: dict[str, Any], path: tuple[str, ...] = ()) -> dict[tuple[str, ...], Any]:
    """Return every leaf of a JSON tree by its path."""
    found: dict[tuple[str, ...], Any] = {}
    for key, item in value.items():
        if isinstance(item, dict):
            found |= leaves(item, (*path, key))
        else:
            found[(*path, key)] = item
    return found


SOURCE = leaves(STRINGS)


@pytest.mark.parametrize("path", FILES, ids=lambda path: path.stem)
def test_every_text_translated(path: Path) -> None:
    """The same texts as strings.json, none empty, each keeping its placeholders."""
    text = path.read_text(encoding="utf-8")
    translated = leaves(json.loads(text))
    assert sorted(SOURCE.keys() - translated.keys()) == []  # missing
    assert sorted(translated.keys() - SOURCE.keys()) == []  # not in strings.json
    for key, english in SOURCE.items():
        words = translated[key]
        assert isinstance(words, str), key
        assert words.strip(), key
        assert set(PLACEHOLDER.findall(words)) == set(PLACEHOLDER.findall(english)), key
        if "data_description" in key:
            assert "`" not in words, key
            assert "**" not in words, key
    assert text == json.dumps(json.loads(text), indent=2, ensure_ascii=False) + "\n"


def test_every_language_there() -> None:
    """Each language PLC Bridge is translated into has its file, and no other file is there."""
    assert {path.stem for path in FILES} == LANGUAGES
