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
CONF_MAC: Final = "mac"
"""Entry data of a PLC added from a DHCP discovery: its MAC, to find it again at a new address."""

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
# Conversions of one point (see conversion.py) and what a button or an alarm word adds.
CONF_VALUE_MAP: Final = "value_map"
CONF_RAW_MIN: Final = "raw_min"
CONF_RAW_MAX: Final = "raw_max"
CONF_SHOWN_MIN: Final = "shown_min"
CONF_SHOWN_MAX: Final = "shown_max"
CONF_PRECISION: Final = "precision"
CONF_INVERT: Final = "invert"
CONF_ON_VALUE: Final = "on_value"
CONF_OFF_VALUE: Final = "off_value"
CONF_PULSE: Final = "pulse"
CONF_BITS: Final = "bits"
CONF_ROLE: Final = "role"
"""The part a point plays in an entity of several points (see composite.py)."""
CONF_AS_TEXT: Final = "as_text"
"""A duration point shown as clock text, hh:mm:ss.zzz (TecoApi TIME/TOD as they showed before)."""
CONF_ENTITY: Final = "entity"
"""The key of the entity of several points a part belongs to (its unique id's end)."""
PULSE_MIN: Final = 0.1
PULSE_MAX: Final = 60.0
"""The shortest and longest pulse of a button, in seconds."""
BIT_LIMIT: Final = 63
"""The highest bit number an alarm word can name (an LWORD's)."""

SUBENTRY_EXPOSE: Final = "expose"
"""A Home Assistant entity's state (or attribute) written to one PLC address: one per subentry."""
CONF_COOLDOWN: Final = "cooldown"
CONF_RESEND: Final = "resend"
CONF_SEND_ON_START: Final = "send_on_start"
CONF_DEFAULT: Final = "default"
"""Expose data: the value written while the entity is unavailable or unknown (absent: none)."""

ATTR_CONFIG_ENTRY_ID: Final = "config_entry_id"
ATTR_POINTS: Final = "points"
ATTR_VALUE: Final = "value"
EVENT_ALARM: Final = "plc_bridge_alarm"
"""Fired on the bus when a named bit of an alarm word changes (the logbook names the alarm)."""
