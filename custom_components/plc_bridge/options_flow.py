"""Options flow of PLC Bridge: the poll interval, never shorter than the vendor allows."""

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

from .const import CONF_VENDOR
from .plc.vendors import client_class
from .points import entry_points

SCHEMA = vol.Schema(
    {
        vol.Required(CONF_SCAN_INTERVAL): NumberSelector(
            NumberSelectorConfig(
                min=0.1,
                max=86400,
                step=0.1,
                mode=NumberSelectorMode.BOX,
                unit_of_measurement=UnitOfTime.SECONDS,
            )
        )
    }
)


class PlcBridgeOptionsFlow(OptionsFlow):
    """Set how often the PLC is polled; the entry's update listener applies it."""

    async def async_step_init(self, user_input: dict[str, Any] | None = None) -> ConfigFlowResult:
        """Ask for the poll interval; refuse one shorter than the vendor's advised rate allows."""
        client = client_class(self.config_entry.data[CONF_VENDOR])
        points = list(dict.fromkeys(c.point for c in entry_points(self.config_entry).values()))
        minimum = client.min_scan_interval(points)
        errors: dict[str, str] = {}
        if user_input is not None:
            interval = float(user_input[CONF_SCAN_INTERVAL])
            if interval < minimum:
                errors[CONF_SCAN_INTERVAL] = "scan_interval_too_short"
            else:
                return self.async_create_entry(
                    data={**self.config_entry.options, CONF_SCAN_INTERVAL: interval}
                )
        current = self.config_entry.options.get(CONF_SCAN_INTERVAL, client.default_scan_interval)
        return self.async_show_form(
            step_id="init",
            data_schema=self.add_suggested_values_to_schema(
                SCHEMA, user_input or {CONF_SCAN_INTERVAL: current}
            ),
            errors=errors,
            description_placeholders={
                "minimum": f"{minimum:g}",
                "cycle": f"{max(float(current), minimum):g}",  # what the coordinator polls at
                "points": str(len(points)),
                "requests": str(client.requests_for(points)),
            },
        )
