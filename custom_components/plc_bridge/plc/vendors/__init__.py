"""The vendor modules, one per PLC network interface, looked up by vendor key."""

from __future__ import annotations

from collections.abc import Mapping
import importlib

from ..client import PlcClient
from ..probe import Probe

VENDORS: tuple[str, ...] = ("s7_smart", "tecomat", "plcnext", "softplc", "s7", "logo")
"""Every vendor key, in the order the config flow lists them."""


def _load() -> tuple[dict[str, type[PlcClient]], dict[str, Probe]]:
    """Import every vendor module that exists, once, when this package is imported.

    Returns each vendor's client class, and its probe where it has one.

    Done at import time so that Home Assistant imports them in its executor with the
    integration, never inside the event loop when a flow first asks for a vendor.
    """
    clients: dict[str, type[PlcClient]] = {}
    probes: dict[str, Probe] = {}
    for vendor in VENDORS:
        try:
            module = importlib.import_module(f"{__name__}.{vendor}")
        except ModuleNotFoundError as err:
            if err.name != f"{__name__}.{vendor}":
                raise
            continue
        clients[vendor] = module.CLIENT
        if hasattr(module, "PROBE"):
            probes[vendor] = module.PROBE
    return clients, probes


_CLIENTS, _PROBES = _load()


def client_class(vendor: str, options: Mapping[str, object] | None = None) -> type[PlcClient]:
    """Return the client class of a vendor; raise KeyError when it is not implemented yet.

    With a PLC's vendor options: the class whose address checks know them (`configured`).
    """
    found = _CLIENTS[vendor]
    return found if options is None else found.configured(options)


def implemented() -> list[str]:
    """Return the vendor keys that have a client module."""
    return list(_CLIENTS)


def probe_of(vendor: str) -> Probe | None:
    """Return the probe telling whether a vendor's interface answers at a host, if it has one."""
    return _PROBES.get(vendor)
