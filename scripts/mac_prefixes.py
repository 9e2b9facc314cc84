"""Print the DHCP matchers of the PLC vendors' MAC prefixes, read from an IEEE OUI registry text.

Usage: .venv/bin/python scripts/mac_prefixes.py path/to/oui.txt [--table]
The registry text is the one the `netaddr` package ships (`netaddr/eui/oui.txt`); it is used
while developing only. Without --table this prints the manifest's `dhcp` list; with --table the
`MAC_PREFIXES` table of custom_components/plc_bridge/flows/mac_prefixes.py.
tests/flows/test_discovery_matchers.py checks both against a committed excerpt of the registry, so
neither can drift from this script.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
import re

BLOCK = re.compile(r"^([0-9A-F]{2})-([0-9A-F]{2})-([0-9A-F]{2})\s+\(hex\)\s+(.+?)\s*$", re.M)

ORGANISATIONS: dict[str, frozenset[str]] = {
    "phoenix_contact": frozenset({"PHOENIX CONTACT Electronics GmbH"}),
    "teco": frozenset({"TECO a.s."}),
    # Siemens registers blocks under many names. Kept: the parent company under its three
    # spellings (its names never say the division, and the S7 CPUs, ET 200 stations, drives
    # and panels of its factory-automation business carry them: the probe tells them apart),
    # and the units named for factory automation: Automations & Drives, Industry Automation
    # (I IA), the drive and motion-control units (SINAMICS, SIMOTION), the Chengdu plant that
    # makes the S7-200 SMART and S7-1200, the Nanjing numerical-control unit (a SINUMERIK's PLC
    # speaks S7comm) and Siemens Industry, Inc. (the US arm of the industry sector).
    # Left out: building technologies, energy and grid (protection relays speak IEC 61850, not
    # S7), healthcare, mobility and rail, telecommunication, home and office, the national
    # companies (Austria, Belgium, Canada, India), low voltage (breakers), and the joint
    # ventures (Fujitsu Siemens, Nokia Siemens): none of them makes a PLC PLC Bridge serves.
    "siemens": frozenset(
        {
            "SIEMENS AG",
            "Siemens AG",
            "Siemens AG,",
            "Siemens AG, Automations & Drives,",
            "Siemens AG I IA PP PRM",
            "Siemens AG, Sector Industry, Drive Technologies, Motion Control Systems",
            "SIEMENS AG, Digital Factory, Motion Control System",
            "Siemens Industrial Automation Products Ltd., Chengdu",
            "Siemens Numerical Control Ltd., Nanjing",
            "Siemens Industry, Inc.",
        }
    ),
    # SoftPLC Corporation has no block in the registry: its runtime runs on others' hardware.
    "softplc": frozenset({"SoftPLC Corporation"}),
}
"""Per PLC family, the registry's organisation names whose blocks it takes, spelt exactly."""


def prefixes(registry: str) -> dict[str, str]:
    """Return the MAC prefixes (six upper-case hex digits) of the families served, sorted."""
    families = {name: family for family, names in ORGANISATIONS.items() for name in names}
    found = {
        f"{a}{b}{c}": families[name]
        for a, b, c, name in BLOCK.findall(registry)
        if name in families
    }
    return dict(sorted(found.items()))


def matchers(table: dict[str, str]) -> list[dict[str, str | bool]]:
    """Return the manifest's `dhcp` list: known devices, then one matcher per prefix."""
    return [{"registered_devices": True}, *({"macaddress": f"{p}*"} for p in sorted(table))]


def main() -> None:
    """Read the registry text named on the command line and print the matchers or the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("registry", type=Path, help="an IEEE OUI registry text (oui.txt)")
    parser.add_argument("--table", action="store_true", help="print MAC_PREFIXES instead")
    args = parser.parse_args()
    table = prefixes(args.registry.read_text(encoding="utf-8", errors="replace"))
    if args.table:
        print("MAC_PREFIXES: dict[str, str] = {")
        for prefix, family in table.items():
            print(f'    "{prefix}": "{family}",')
        print("}")
        return
    print(json.dumps(matchers(table), indent=2))


if __name__ == "__main__":
    main()
