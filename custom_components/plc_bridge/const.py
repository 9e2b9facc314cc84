"""Constants of the PLC Bridge integration."""

from __future__ import annotations

import logging
from typing import Final

from homeassistant.const import Platform

DOMAIN: Final = "plc_bridge"
LOGGER = logging.getLogger(__package__)

CONF_VENDOR: Final = "vendor"
CONF_TLS: Final = "tls"
CONF_FINGERPRINT: Final = "fingerprint"
CONF_OPTIONS: Final = "vendor_options"

SUBENTRY_POINT: Final = "point"
"""The subentry type of config entry version 1: one point per subentry (migrated to devices)."""
SUBENTRY_DEVICE: Final = "device"
"""A machine or part of the plant: its own Home Assistant device, holding any number of points."""
CONF_POINTS: Final = "points"
"""Device subentry data: {point id: point data}; the point id is part of the entity's unique id."""
CONF_AREA: Final = "area"
"""Device subentry data: the suggested area of the device (optional)."""
CONF_PLATFORM: Final = "platform"
CONF_ADDRESS: Final = "address"
CONF_DATA_TYPE: Final = "data_type"
CONF_SCALE: Final = "scale"
CONF_OFFSET: Final = "offset"
CONF_READ_ONLY: Final = "read_only"
CONF_MIN: Final = "min"
CONF_MAX: Final = "max"
CONF_STEP: Final = "step"

PLATFORMS: Final = [
    Platform.BINARY_SENSOR,
    Platform.DATETIME,
    Platform.NUMBER,
    Platform.SENSOR,
    Platform.SWITCH,
    Platform.TEXT,
]
POINT_PLATFORMS: Final = ("sensor", "binary_sensor", "switch", "number", "datetime", "text")

ATTR_CONFIG_ENTRY_ID: Final = "config_entry_id"
ATTR_POINTS: Final = "points"
ATTR_VALUE: Final = "value"
