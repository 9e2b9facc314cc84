"""TecoApi GetInfo (3.2): device information, PLC mode, user program and PLC time."""

from __future__ import annotations

from datetime import tzinfo
from typing import Any

from ...errors import PlcProtocolError
from ...types import DeviceInfo, PlcStatus
from .codec import parse_datetime

MODES = {"RUN": "RUN", "HALT": "HALT", "ERR": "ERROR"}
"""GetInfo's plc.mode (the spec sends "RUN " with a space) to the vendor-neutral words."""


def _plc(info: Any) -> dict[str, Any]:
    """Return the plc block of a GetInfo answer."""
    plc = info.get("plc") if isinstance(info, dict) else None
    if not isinstance(plc, dict):
        raise PlcProtocolError("the PLC's GetInfo answer has no plc block")
    return plc


def _text(block: Any, key: str) -> str | None:
    """Return a non-empty text field of a block, stripped."""
    value = block.get(key) if isinstance(block, dict) else None
    return value.strip() or None if isinstance(value, str) else None


def device_info(info: Any) -> DeviceInfo:
    """Return what GetInfo says about the PLC; the serial number is its unique id."""
    plc = _plc(info)
    family, cpu = _text(plc, "family"), _text(plc, "type")
    extra = {
        "api": _text(info.get("api"), "version"),
        "family": family,
        "cpu": cpu,
        "program": _text(plc.get("userProg"), "name"),
    }
    return DeviceInfo(
        vendor="tecomat",
        model=" ".join(part for part in (family, cpu) if part) or "Tecomat",
        serial=_text(plc, "serialNumber"),
        mac=_text(plc, "mac"),
        firmware=_text(plc, "version"),
        extra={key: value for key, value in extra.items() if value},
    )


def plc_status(info: Any, zone: tzinfo) -> PlcStatus:
    """Return the PLC mode, its clock and the user program (name, compile time, stamp)."""
    plc = _plc(info)
    mode = _text(plc, "mode")
    time = _text(plc, "time")
    program = plc.get("userProg")
    compiled = _text(program, "compiled")
    # The same DT form as the clock (PLC digits): passed on with its offset, ISO 8601.
    moment = parse_datetime("DT", compiled, zone) if compiled else None
    extra = {
        "program": _text(program, "name"),
        "program_compiled": moment.isoformat() if moment else compiled,
        "program_stamp": _text(program, "stamp"),
    }
    return PlcStatus(
        mode=MODES.get(mode.upper(), mode) if mode else None,
        clock=parse_datetime("DT", time, zone) if time else None,
        extra={key: value for key, value in extra.items() if value},
    )
