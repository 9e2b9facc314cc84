"""Constants of the PLC Bridge integration."""

from __future__ import annotations

import logging
from typing import Final

DOMAIN: Final = "plc_bridge"
LOGGER = logging.getLogger(__package__)

CONF_VENDOR: Final = "vendor"
CONF_TLS: Final = "tls"
CONF_FINGERPRINT: Final = "fingerprint"
CONF_OPTIONS: Final = "vendor_options"

SUBENTRY_POINT: Final = "point"
CONF_PLATFORM: Final = "platform"
CONF_ADDRESS: Final = "address"
CONF_DATA_TYPE: Final = "data_type"
CONF_SCALE: Final = "scale"
CONF_OFFSET: Final = "offset"
CONF_READ_ONLY: Final = "read_only"
CONF_MIN: Final = "min"
CONF_MAX: Final = "max"
CONF_STEP: Final = "step"

POINT_PLATFORMS: Final = ("sensor", "binary_sensor", "switch", "number", "datetime", "text")

ATTR_CONFIG_ENTRY_ID: Final = "config_entry_id"
ATTR_POINTS: Final = "points"
ATTR_VALUE: Final = "value"
