"""Protocol-layer fixtures: simulators on loopback and clients connected to them.

Each vendor's live in one module, tests/plc/<vendor>_fixtures.py, started and stopped through
tests/loopback.py, and are imported into this conftest so they exist here and nowhere else.
(`pytest_plugins` in a test module would register them for the whole run.) The Home Assistant
tests' simulators have names of their own (`<family>_ha_sim`, tests/harness.py).
"""

from __future__ import annotations

from tests.loopback import ConfigFactory

from .plcnext_fixtures import plcnext_client, plcnext_config, plcnext_sim
from .s7_smart_fixtures import s7_smart_client, s7_smart_config, s7_smart_sim
from .softplc_fixtures import (
    softplc_client,
    softplc_reading,
    softplc_settings,
    softplc_sim,
    softplc_tls_sim,
)
from .tecomat_fixtures import basic_sim, tecomat_client, tecomat_config, tecomat_sim

__all__ = [
    "ConfigFactory",
    "basic_sim",
    "plcnext_client",
    "plcnext_config",
    "plcnext_sim",
    "s7_smart_client",
    "s7_smart_config",
    "s7_smart_sim",
    "softplc_client",
    "softplc_reading",
    "softplc_settings",
    "softplc_sim",
    "softplc_tls_sim",
    "tecomat_client",
    "tecomat_config",
    "tecomat_sim",
]
