"""Options flow of PLC Bridge: the poll intervals, never shorter than the vendor allows."""

from __future__ import annotations

from typing import Any

from homeassistant.config_entries import ConfigFlowResult, OptionsFlow
from homeassistant.const import CONF_SCAN_INTERVAL, UnitOfTime
from homeassistant.helpers.selector import (
    NumberSelector,
    NumberSelectorConfig,
    NumberSelectorMode,
)
import voluptuous as vol

from .availability import MachineAvailability
from .const import CONF_VENDOR
from .plc import PlcClient
from .plc.vendors import client_class
from .points import entry_points, point_classes
from .poll_classes import (
    CONF_FAST_INTERVAL,
    CONF_SLOW_INTERVAL,
    DEFAULT_FAST_INTERVAL,
    DEFAULT_SLOW_INTERVAL,
    FAST,
    NORMAL,
    class_minimums,
)

SECONDS_MIN = 0.1
SECONDS_MAX = 86400.0
"""The bounds of every poll interval, in seconds: the form's fields and the pasted file's."""
SECONDS = NumberSelector(
    NumberSelectorConfig(
        min=SECONDS_MIN,
        max=SECONDS_MAX,
        step=0.1,
        mode=NumberSelectorMode.BOX,
        unit_of_measurement=UnitOfTime.SECONDS,
    )
)
INTERVALS = (CONF_FAST_INTERVAL, CONF_SCAN_INTERVAL, CONF_SLOW_INTERVAL)
SCHEMA = vol.Schema(
    {
        vol.Optional(CONF_FAST_INTERVAL): SECONDS,
        vol.Required(CONF_SCAN_INTERVAL): SECONDS,
        vol.Optional(CONF_SLOW_INTERVAL): SECONDS,
    }
)


def interval_errors(intervals: dict[str, float], minimums: dict[str, float]) -> dict[str, str]:
    """Return the errors of the intervals by field: below the vendor's pace, or out of order."""
    fast, normal = intervals[CONF_FAST_INTERVAL], intervals[CONF_SCAN_INTERVAL]
    errors: dict[str, str] = {}
    if normal < minimums[NORMAL]:
        errors[CONF_SCAN_INTERVAL] = "scan_interval_too_short"
    if fast < minimums[FAST]:
        errors[CONF_FAST_INTERVAL] = "fast_interval_too_short"
    elif fast > normal:
        errors[CONF_FAST_INTERVAL] = "fast_above_normal"
    if intervals[CONF_SLOW_INTERVAL] < normal:
        errors[CONF_SLOW_INTERVAL] = "slow_below_normal"
    return errors


def unset(
    client: type[PlcClient], intervals: dict[str, float], minimums: dict[str, float]
) -> dict[str, float]:
    """Return the intervals with those not set yet filled in: defaults, kept in order."""
    normal = intervals.get(CONF_SCAN_INTERVAL, client.default_scan_interval)
    fast = min(max(DEFAULT_FAST_INTERVAL, minimums[FAST]), max(normal, minimums[FAST]))
    slow = max(DEFAULT_SLOW_INTERVAL, normal)
    defaults = {CONF_FAST_INTERVAL: fast, CONF_SCAN_INTERVAL: normal, CONF_SLOW_INTERVAL: slow}
    return defaults | intervals


class PlcBridgeOptionsFlow(OptionsFlow):
    """Set how often the PLC is polled; the entry's update listener applies it."""

    async def async_step_init(self, user_input: dict[str, Any] | None = None) -> ConfigFlowResult:
        """Ask for the poll intervals; refuse those the vendor's pace or their order forbid."""
        client = client_class(self.config_entry.data[CONF_VENDOR])
        configs = entry_points(self.config_entry)
        availability = MachineAvailability(self.config_entry.title)
        availability.configure(self.config_entry.subentries.values())
        points = list(dict.fromkeys(c.point for c in configs.values()))
        polled = list(dict.fromkeys([*availability.points.values(), *points]))
        classes = point_classes(configs, availability.points.values())
        minimums = class_minimums(client, classes, polled)
        options = self.config_entry.options
        current = {key: float(options[key]) for key in INTERVALS if key in options}
        errors: dict[str, str] = {}
        if user_input is not None:
            given = {key: float(value) for key, value in user_input.items() if key in INTERVALS}
            errors = interval_errors(unset(client, current | given, minimums), minimums)
            if not errors:
                return self.async_create_entry(data={**options, **given})
        current = unset(client, current, minimums)
        return self.async_show_form(
            step_id="init",
            data_schema=self.add_suggested_values_to_schema(SCHEMA, user_input or current),
            errors=errors,
            description_placeholders={
                "minimum": f"{minimums[NORMAL]:g}",
                "fast_minimum": f"{minimums[FAST]:g}",
                # what the coordinator polls at
                "cycle": f"{max(current[CONF_SCAN_INTERVAL], minimums[NORMAL]):g}",
                "points": str(len(points)),
                "requests": str(client.requests_for(points)),
            },
        )
