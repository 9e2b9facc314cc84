"""A LOGO!'s connection options: its generation and the TSAPs of its server connection.

A LOGO! serves S7 clients only through a server connection set up in LOGO!Soft Comfort (or,
on a LOGO! 8, its "access for HMI"): no rack and slot. Each generation's defaults are what
public guides use (simulators/logo/READINGS.md, row 1); the user enters those of the PLC.
"""

from __future__ import annotations

from collections.abc import Mapping

from ...errors import PlcOptionError
from ..s7.link import parse_tsap, tsap_text
from .address import GENERATIONS

DEFAULT_TSAPS: dict[str, tuple[str, str]] = {
    "0ba7": ("10.01", "10.00"),  # local, remote: the 0BA7 guide for ISO-on-TCP HMIs (InduSoft)
    "0ba8": ("02.00", "20.00"),  # the LOGO! side 20.00 as in python-snap7's Logo and Snap7
    "8_x": ("02.00", "20.00"),
}


def validate_options(options: Mapping[str, object]) -> dict[str, str | int | bool]:
    """Return "generation", "local_tsap" and "remote_tsap" normalized; raise PlcOptionError.

    A TSAP left out takes the generation's default. Other keys are left out.
    """
    generation = options.get("generation", "0ba8")
    if generation not in GENERATIONS:
        raise PlcOptionError(
            f"generation must be one of {', '.join(GENERATIONS)}, not {generation!r:.40}",
            "generation",
        )
    local, remote = DEFAULT_TSAPS[str(generation)]
    given = {
        key: options.get(key) if options.get(key) not in (None, "") else default
        for key, default in (("local_tsap", local), ("remote_tsap", remote))
    }
    return {
        "generation": str(generation),
        "local_tsap": tsap_text(parse_tsap(given["local_tsap"], "local_tsap")),
        "remote_tsap": tsap_text(parse_tsap(given["remote_tsap"], "remote_tsap")),
    }


def s7_options(options: Mapping[str, object]) -> dict[str, str | int | bool]:
    """Return the S7 transport's options for a LOGO!'s (a connection by TSAP)."""
    checked = validate_options(options)
    return {
        "connection": "tsap",
        "local_tsap": checked["local_tsap"],
        "remote_tsap": checked["remote_tsap"],
    }
