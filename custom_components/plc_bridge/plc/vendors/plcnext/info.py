"""What the PLCnext REST interface says about the PLC: API version, program CRC, user check.

The sources name no device model, firmware or serial number in the REST interface: the
service description gives the API version, every data answer the HMI project's checksum
(`projectCRC`) and `userAuthenticationRequired`. Fields a firmware adds under the names below
are shown where present; none is ever required.
"""

from __future__ import annotations

from datetime import datetime
from typing import Any

from ...types import DeviceInfo, PlcStatus
from .api import PlcnextApi

MODEL = "PLCnext Control"
_MODEL_KEYS = ("productName", "deviceName", "model")
_FIRMWARE_KEYS = ("firmwareVersion", "firmware")
_SERIAL_KEYS = ("serialNumber", "serial")


def _text(description: Any, keys: tuple[str, ...]) -> str | None:
    """Return the first non-empty text field of the description among the keys."""
    if not isinstance(description, dict):
        return None
    for key in keys:
        value = description.get(key)
        if isinstance(value, str | int) and not isinstance(value, bool) and str(value).strip():
            return str(value).strip()
    return None


def device_info(description: Any, api: PlcnextApi) -> DeviceInfo:
    """Return the device as the service description reports it, and the API version pinned."""
    version = _text(description, ("apiVersion", "version"))
    crc = _text(description, ("projectCRC",))
    extra = {
        "api_version": version,
        "api_path": api.base,
        "project_crc": crc,
        "user_authentication": (
            None if api.auth_required is None else ("on" if api.auth_required else "off")
        ),
        "session": "yes" if api.session_id else "no",
    }
    firmware = _text(description, _FIRMWARE_KEYS)
    return DeviceInfo(
        vendor="plcnext",
        model=_text(description, _MODEL_KEYS) or MODEL,
        serial=_text(description, _SERIAL_KEYS),
        firmware=firmware or (f"REST API {version}" if version else None),
        extra={key: value for key, value in extra.items() if value},
    )


def plc_status(crc: Any, regroups: int, clock: Any = None) -> PlcStatus:
    """Return the poll's status: the HMI project's checksum (a download changes it), the clock."""
    extra: dict[str, str] = {}
    if isinstance(crc, int | str) and not isinstance(crc, bool):
        extra["project_crc"] = str(crc)
    if regroups:
        extra["groups_registered_again"] = str(regroups)
    return PlcStatus(clock=clock if isinstance(clock, datetime) else None, extra=extra)
