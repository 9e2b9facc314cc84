"""The manifest's DHCP matchers: made by scripts/mac_prefixes.py, as Home Assistant reads them."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path
from types import ModuleType

from homeassistant.core import HomeAssistant
from homeassistant.loader import async_get_dhcp
import pytest

from custom_components.plc_bridge.const import DOMAIN
from custom_components.plc_bridge.flows.mac_prefixes import FAMILIES, MAC_PREFIXES, family_of
from custom_components.plc_bridge.plc.vendors import probe_of

ROOT = Path(__file__).resolve().parents[2]
MANIFEST = json.loads((ROOT / "custom_components/plc_bridge/manifest.json").read_text())
REGISTRY = (Path(__file__).parent / "oui_excerpt.txt").read_text(encoding="utf-8")
"""The registry's blocks of every organisation named Siemens, Phoenix Contact or Teco."""


def script() -> ModuleType:
    """Import scripts/mac_prefixes.py (a development tool, not a package)."""
    spec = importlib.util.spec_from_file_location("mac_prefixes", ROOT / "scripts/mac_prefixes.py")
    assert spec is not None
    assert spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_table_is_the_scripts() -> None:
    """MAC_PREFIXES is what the script finds in the registry: none added or lost by hand."""
    assert script().prefixes(REGISTRY) == MAC_PREFIXES


def test_manifest_is_the_scripts() -> None:
    """The manifest's dhcp list is the script's: known devices, then one matcher per prefix."""
    assert MANIFEST["dhcp"] == script().matchers(MAC_PREFIXES)
    assert MANIFEST["dhcp"][0] == {"registered_devices": True}
    for matcher in MANIFEST["dhcp"][1:]:
        assert len(matcher["macaddress"]) == 7
        assert matcher["macaddress"] == matcher["macaddress"].upper()


def test_organisations() -> None:
    """The makers' blocks named in the issue are in; other Siemens companies and lookalikes not."""
    assert MAC_PREFIXES["00A045"] == "phoenix_contact"
    assert MAC_PREFIXES["000A14"] == "teco"
    assert MAC_PREFIXES["8CF319"] == "siemens"  # Siemens Industrial Automation, Chengdu
    for refused in ("00C0E4", "000519", "001865", "000B23", "009040", "DC0575", "003005"):
        assert refused not in MAC_PREFIXES, refused  # building, health, home, grid, Fujitsu
    assert "SoftPLC Corporation" in script().ORGANISATIONS["softplc"]  # none registered yet


def test_families_have_probes() -> None:
    """Every family a prefix names exists, and every interface it is probed for has a probe."""
    assert set(MAC_PREFIXES.values()) <= set(FAMILIES)
    for family in FAMILIES.values():
        assert all(probe_of(vendor) is not None for vendor in family.vendors)
    assert family_of("00:A0:45:01:02:03") is FAMILIES["phoenix_contact"]
    assert family_of("00a045010203") is FAMILIES["phoenix_contact"]
    assert family_of("00:A1:45:01:02:03") is None


@pytest.mark.parametrize(
    ("mac", "matched"),
    [
        ("286336A1B2C3", True),  # Siemens AG
        ("000A14123456", True),  # TECO a.s.
        ("CCCCEA000001", True),  # PHOENIX CONTACT Electronics GmbH
        ("00A0030000FF", False),  # Siemens Switzerland, building technologies
        ("0030050000FF", False),  # Fujitsu Siemens Computers
        ("AABBCC000000", False),
    ],
)
async def test_home_assistant_matches(hass: HomeAssistant, mac: str, matched: bool) -> None:
    """Home Assistant's matchers from every manifest send only the makers' MACs here.

    As its DHCP watcher indexes them (components/dhcp: by the pattern's first six characters,
    looked up with the MAC's upper-case first six; its watcher's packages are not installed).
    """
    matchers = [m for m in await async_get_dhcp(hass) if m["domain"] == DOMAIN]
    assert {"domain": DOMAIN, "registered_devices": True} in matchers
    prefixes = {m["macaddress"][:6] for m in matchers if "macaddress" in m}
    assert (mac.upper()[:6] in prefixes) is matched
