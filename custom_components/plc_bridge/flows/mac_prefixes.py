"""The PLC makers' MAC prefixes the manifest's DHCP matchers name, and what each is probed for.

MAC_PREFIXES is printed by `scripts/mac_prefixes.py --table` from the IEEE registry; a test
checks it, and the manifest, against the script's output for a committed excerpt of it.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Family:
    """A maker whose MAC prefix was seen, and the interfaces of its PLCs PLC Bridge implements."""

    name: str  # the maker, as the discovered PLC's card and form name it
    vendors: tuple[str, ...]  # the vendor keys probed, in the order offered (the first preferred)


FAMILIES: dict[str, Family] = {
    # An S7-200 SMART also answers S7comm: its Web API, where it answers, is the one preferred.
    "siemens": Family("Siemens", ("s7_smart", "s7", "logo")),
    "phoenix_contact": Family("Phoenix Contact", ("plcnext",)),
    "teco": Family("Teco", ("tecomat",)),
}

MAC_PREFIXES: dict[str, str] = {
    "0001E3": "siemens",
    "000A14": "teco",
    "000BA3": "siemens",
    "000E8C": "siemens",
    "001B1B": "siemens",
    "001C06": "siemens",
    "001FF8": "siemens",
    "00A045": "phoenix_contact",
    "080006": "siemens",
    "10DFFC": "siemens",
    "208756": "siemens",
    "20A8B9": "siemens",
    "286336": "siemens",
    "301389": "siemens",
    "302F1E": "siemens",
    "30B851": "siemens",
    "384B24": "siemens",
    "40ECF8": "siemens",
    "4CE705": "siemens",
    "681FD8": "siemens",
    "683E02": "siemens",
    "789F87": "siemens",
    "883F99": "siemens",
    "8CF319": "siemens",
    "A8741D": "phoenix_contact",
    "AC6417": "siemens",
    "CCCCEA": "phoenix_contact",
    "D4F527": "siemens",
    "E0DCA0": "siemens",
    "E8EF22": "siemens",
    "EC1C5D": "siemens",
}
"""Per MAC prefix (six upper-case hex digits), its maker: a key of FAMILIES."""


def family_of(mac: str) -> Family | None:
    """Return the maker of a MAC address (any separators, any case), or None when not served."""
    digits = "".join(char for char in mac if char.isalnum()).upper()
    family = MAC_PREFIXES.get(digits[:6])
    return FAMILIES[family] if family is not None else None
