"""The keys each level of a stored PLC may hold, and the kind of value each key takes.

One list per level, in one place: the PLC file takes these keys and no other (a key the forms
never store is refused on its line, never stored), and each value must be of its key's kind.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Final

from homeassistant.components.sensor import CONF_STATE_CLASS
from homeassistant.const import (
    CONF_ATTRIBUTE,
    CONF_DEVICE_CLASS,
    CONF_ENTITY_ID,
    CONF_HOST,
    CONF_NAME,
    CONF_PASSWORD,
    CONF_PORT,
    CONF_SCAN_INTERVAL,
    CONF_UNIT_OF_MEASUREMENT,
    CONF_USERNAME,
)

from ..const import (
    CONF_ADDRESS,
    CONF_AREA,
    CONF_AS_TEXT,
    CONF_BITS,
    CONF_COOLDOWN,
    CONF_DATA_TYPE,
    CONF_DEFAULT,
    CONF_ENTITY,
    CONF_FINGERPRINT,
    CONF_INVERT,
    CONF_MAX,
    CONF_MIN,
    CONF_OFF_VALUE,
    CONF_OFFSET,
    CONF_ON_VALUE,
    CONF_OPTIONS,
    CONF_PLATFORM,
    CONF_POINTS,
    CONF_PRECISION,
    CONF_PULSE,
    CONF_RAW_MAX,
    CONF_RAW_MIN,
    CONF_READ_ONLY,
    CONF_RESEND,
    CONF_ROLE,
    CONF_SCALE,
    CONF_SEND_ON_START,
    CONF_SHOWN_MAX,
    CONF_SHOWN_MIN,
    CONF_STEP,
    CONF_TLS,
    CONF_VALUE_MAP,
    CONF_VENDOR,
    SUBENTRY_DEVICE,
    SUBENTRY_EXPOSE,
    SUBENTRY_POINT,
)
from .availability import (
    CONF_AVAILABILITY_ADDRESS,
    CONF_AVAILABILITY_DATA_TYPE,
    CONF_AVAILABILITY_POLICY,
    CONF_AVAILABILITY_VALUES,
)
from .expose import CONF_SEND
from .kinds import CONF_SUPERVISION, CONF_TRAVEL_TIME
from .poll_classes import CONF_FAST_INTERVAL, CONF_POLL, CONF_SLOW_INTERVAL
from .template import CONF_COPY_OF, CONF_TEMPLATE
from .vendor_fields import SECOND_PAGES, VENDOR_FIELDS

TEXT: Final = "text"
NUMBER: Final = "number"
WHOLE: Final = "whole number"
SWITCH: Final = "true or false"
MAPPING: Final = "mapping"
LIST: Final = "list"
SCALAR: Final = "text, number or true/false"
NULLABLE: Final = " or null"
"""A kind's suffix: the key may also hold null."""

type Keys = Mapping[str, str]
"""Keys of one level and the kind of value each takes."""

FILE: Keys = {
    "plc_bridge": WHOLE,
    "version": WHOLE,
    "minor_version": WHOLE,
    "title": TEXT,
    "connection": MAPPING,
    "secrets": LIST,
    "options": MAPPING,
    "subentries": LIST,
}
CONNECTION: Keys = {
    CONF_VENDOR: TEXT,
    CONF_HOST: TEXT,
    CONF_PORT: WHOLE,
    CONF_TLS: TEXT,
    CONF_FINGERPRINT: TEXT,
    CONF_USERNAME: TEXT,
    CONF_PASSWORD: TEXT,
    CONF_OPTIONS: MAPPING,
}
"""Entry data. Not the MAC a discovery stored: it belongs to the installation that found it."""
OPTIONS: Keys = {
    CONF_SCAN_INTERVAL: NUMBER,
    CONF_FAST_INTERVAL: NUMBER,
    CONF_SLOW_INTERVAL: NUMBER,
}
SUBENTRY: Keys = {"type": TEXT, "title": TEXT, "unique_id": TEXT + NULLABLE, "data": MAPPING}
DEVICE: Keys = {
    CONF_POINTS: MAPPING,
    CONF_AREA: TEXT + NULLABLE,
    CONF_AVAILABILITY_ADDRESS: TEXT,
    CONF_AVAILABILITY_DATA_TYPE: TEXT,
    CONF_AVAILABILITY_VALUES: LIST,
    CONF_TEMPLATE: MAPPING,
    CONF_COPY_OF: MAPPING,
}
POINT: Keys = {
    CONF_NAME: TEXT,
    CONF_PLATFORM: TEXT,
    CONF_ADDRESS: TEXT,
    CONF_DATA_TYPE: TEXT,
    CONF_SCALE: NUMBER,
    CONF_OFFSET: NUMBER,
    CONF_READ_ONLY: SWITCH,
    CONF_MIN: NUMBER,
    CONF_MAX: NUMBER,
    CONF_STEP: NUMBER,
    CONF_VALUE_MAP: TEXT,
    CONF_RAW_MIN: NUMBER,
    CONF_RAW_MAX: NUMBER,
    CONF_SHOWN_MIN: NUMBER,
    CONF_SHOWN_MAX: NUMBER,
    CONF_PRECISION: WHOLE + NULLABLE,
    CONF_INVERT: SWITCH,
    CONF_ON_VALUE: SCALAR,
    CONF_OFF_VALUE: SCALAR,
    CONF_PULSE: NUMBER,
    CONF_BITS: TEXT,
    CONF_ROLE: TEXT + NULLABLE,
    CONF_AS_TEXT: SWITCH,
    CONF_ENTITY: TEXT,
    CONF_POLL: TEXT,
    CONF_TRAVEL_TIME: NUMBER,
    CONF_SUPERVISION: NUMBER,
    CONF_AVAILABILITY_POLICY: TEXT,
    CONF_DEVICE_CLASS: TEXT + NULLABLE,
    CONF_UNIT_OF_MEASUREMENT: TEXT + NULLABLE,
    CONF_STATE_CLASS: TEXT + NULLABLE,
}
"""A point of a machine; a version 1 point subentry holds the same, less its name."""
EXPOSE: Keys = {
    CONF_ENTITY_ID: TEXT,
    CONF_ATTRIBUTE: TEXT,
    CONF_ADDRESS: TEXT,
    CONF_DATA_TYPE: TEXT,
    CONF_SCALE: NUMBER,
    CONF_OFFSET: NUMBER,
    CONF_VALUE_MAP: TEXT,
    CONF_COOLDOWN: NUMBER,
    CONF_RESEND: NUMBER,
    CONF_SEND_ON_START: SWITCH,
    CONF_SEND: SWITCH,
    CONF_DEFAULT: TEXT,
}
SUBENTRY_DATA: Mapping[str, Keys] = {
    SUBENTRY_DEVICE: DEVICE,
    SUBENTRY_EXPOSE: EXPOSE,
    SUBENTRY_POINT: POINT,
}


def vendor_option_keys(vendor: str) -> Keys:
    """Return the vendor options its connection pages store (every way of the second page)."""
    fields = list(VENDOR_FIELDS.get(vendor, ()))
    if (page := SECOND_PAGES.get(vendor)) is not None:
        fields += [field for way in page.ways.values() for field in way]
    return {field.key: SCALAR for field in fields}


def kind_error(kind: str, value: Any) -> bool:
    """True when a value is not of the kind (a string where a number belongs, ...)."""
    if value is None:
        return not kind.endswith(NULLABLE)
    base = kind.removesuffix(NULLABLE)
    if base == NUMBER:
        return isinstance(value, bool) or not isinstance(value, int | float)
    if base == WHOLE:
        return isinstance(value, bool) or not isinstance(value, int)
    checks: dict[str, type | tuple[type, ...]] = {
        TEXT: str,
        SWITCH: bool,
        MAPPING: dict,
        LIST: list,
        SCALAR: (str, int, float),
    }
    return not isinstance(value, checks[base])
