"""Diagnostics: settings, points, device, last status and request counters, credentials hidden."""

from __future__ import annotations

from dataclasses import asdict
from typing import Any

from homeassistant.components.diagnostics import async_redact_data
from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_USERNAME
from homeassistant.core import HomeAssistant

from .const import CONF_AREA, CONF_FINGERPRINT, SUBENTRY_DEVICE, SUBENTRY_EXPOSE
from .coordinator import PlcBridgeConfigEntry
from .model.availability import AVAILABILITY_FIELDS
from .services import json_value

TO_REDACT = {
    CONF_PASSWORD,
    CONF_USERNAME,
    CONF_HOST,
    # The pin identifies one reachable device as surely as its address does.
    CONF_FINGERPRINT,
    "serial",
    "mac",
    "token",
    "cookie",
    # A SoftPLC's client certificate and its private key (the key alone would let anyone write).
    "client_certificate",
    "client_key",
    # Titles are "<model> (<host>)" unless the user renamed the entry.
    "title",
}


async def async_get_config_entry_diagnostics(
    hass: HomeAssistant, entry: PlcBridgeConfigEntry
) -> dict[str, Any]:
    """Return what helps to understand a PLC's behaviour, without where it is or how to log in."""
    runtime = entry.runtime_data
    coordinator = runtime.coordinator
    data = coordinator.data
    status = asdict(data.status) | {"clock": json_value(data.status.clock)}
    return {
        "entry": async_redact_data(
            {"title": entry.title, "data": dict(entry.data), "options": dict(entry.options)},
            TO_REDACT,
        ),
        "points": {
            point_id: {"device": entry.subentries[config.subentry_id].title, **config.stored()}
            for point_id, config in runtime.points.configs.items()
        },
        "machines": {
            subentry.title: {
                CONF_AREA: subentry.data.get(CONF_AREA),
                **{key: subentry.data[key] for key in AVAILABILITY_FIELDS if key in subentry.data},
                "data_valid": sid not in coordinator.availability.invalid,
            }
            for sid, subentry in entry.subentries.items()
            if subentry.subentry_type == SUBENTRY_DEVICE
        },
        "exposes": {
            subentry_id: {"title": subentry.title, **subentry.data}
            for subentry_id, subentry in entry.subentries.items()
            if subentry.subentry_type == SUBENTRY_EXPOSE
        },
        "device": async_redact_data(asdict(runtime.device), TO_REDACT),
        "status": status,
        "results": {
            f"{point.address}|{point.data_type}": {"ok": result.ok, "error": str(result.error)}
            if result.error
            else {"ok": True, "value": json_value(result.value)}
            for point, result in data.values.items()
        },
        "poll": {
            "interval_s": coordinator.update_interval.total_seconds()
            if coordinator.update_interval
            else None,
            # Start to start of the last two polls: longer than the interval where pacing is.
            "last_cycle_s": round(coordinator.cycle, 3) if coordinator.cycle is not None else None,
            "planned_requests": runtime.client.planned_requests(list(data.values)),
            # Each poll class with points: its interval and how many points it has.
            "classes": {
                name: {"interval_s": coordinator.poll_intervals[name], "points": count}
                for name, count in coordinator.poll_counts.items()
            },
            "last_update_success": coordinator.last_update_success,
        },
        "metrics": runtime.client.metrics.as_dict(),
    }
