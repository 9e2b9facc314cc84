"""The buttons of the PLC Bridge page: Home Assistant's and ours say different things.

Home Assistant labels its own buttons by the manifest's integration type ("Add hub", "Add device")
and gives every device row an "Edit device" button (name and area); the subentry flow's buttons
take `config_subentries.<type>.initiate_flow` from strings.json.
"""

from __future__ import annotations

import json
from pathlib import Path
import re
from typing import Any

from custom_components.plc_bridge.const import SUBENTRY_DEVICE

INTEGRATION = Path(__file__).resolve().parents[2] / "custom_components" / "plc_bridge"
STRINGS: dict[str, Any] = json.loads((INTEGRATION / "strings.json").read_text(encoding="utf-8"))
MANIFEST: dict[str, Any] = json.loads((INTEGRATION / "manifest.json").read_text(encoding="utf-8"))
HA_LABELS = {"Add device", "Add hub", "Add service", "Add entry", "Edit device"}


def test_a_plc_is_a_hub() -> None:
    """A PLC runs several machines: Home Assistant's button adds a hub, not a device."""
    assert MANIFEST["integration_type"] == "hub"


def test_machine_buttons_differ_from_home_assistant_s() -> None:
    """Adding and editing a machine are worded apart from adding a PLC or editing a device."""
    machine = STRINGS["config_subentries"][SUBENTRY_DEVICE]
    labels = [machine["initiate_flow"]["user"], machine["initiate_flow"]["reconfigure"]]
    assert machine["entry_type"] == "Machine"
    assert len(set(labels)) == 2
    assert not set(labels) & HA_LABELS


def leaves(value: Any) -> list[str]:
    """Return every string of a JSON tree."""
    if isinstance(value, dict):
        return [text for item in value.values() for text in leaves(item)]
    return [value]


def test_no_text_says_subentry() -> None:
    """ "Subentry" is Home Assistant's word for the code, never shown to a user."""
    assert not [text for text in leaves(STRINGS) if re.search(r"subentr", text, re.IGNORECASE)]


def test_no_count_before_a_plural() -> None:
    """A number the code fills in never stands before a plural noun ("1 points")."""
    counts = re.compile(r"\{(count|points|requests|shown)\} [a-z]+s\b")
    assert not [text for text in leaves(STRINGS) if counts.search(text)]
