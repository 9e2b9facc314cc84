"""The vendor modules, one per PLC network interface, looked up by vendor key."""

from __future__ import annotations

import importlib

from ..client import PlcClient

VENDORS: tuple[str, ...] = ("s7_smart", "tecomat", "plcnext", "softplc", "s7")
"""Every vendor key, in the order the config flow lists them."""


def client_class(vendor: str) -> type[PlcClient]:
    """Return the client class of a vendor; raise KeyError when it is not implemented yet."""
    if vendor not in VENDORS:
        raise KeyError(vendor)
    try:
        module = importlib.import_module(f"{__name__}.{vendor}")
    except ModuleNotFoundError as err:
        if err.name != f"{__name__}.{vendor}":
            raise
        raise KeyError(vendor) from err
    client: type[PlcClient] = module.CLIENT
    return client


def implemented() -> list[str]:
    """Return the vendor keys that have a client module."""
    found = []
    for vendor in VENDORS:
        try:
            client_class(vendor)
        except KeyError:
            continue
        found.append(vendor)
    return found
