"""Options flow of PLC Bridge: the poll intervals, and the PLC's file to copy (Export)."""

from __future__ import annotations

import re
from typing import Any

from homeassistant.config_entries import ConfigFlowResult, OptionsFlow
from homeassistant.const import CONF_SCAN_INTERVAL, UnitOfTime
from homeassistant.helpers.selector import (
    NumberSelector,
    NumberSelectorConfig,
    NumberSelectorMode,
)
import voluptuous as vol

from ..const import CONF_OPTIONS, CONF_VENDOR
from ..model.config_file import dump_config
from ..model.plc_config import PlcConfig
from ..model.poll_classes import (
    CONF_FAST_INTERVAL,
    CONF_SLOW_INTERVAL,
    FAST,
    INTERVALS,
    NORMAL,
    SECONDS_MAX,
    SECONDS_MIN,
    unset,
)
from ..plc.vendors import client_class

SECONDS = NumberSelector(
    NumberSelectorConfig(
        min=SECONDS_MIN,
        max=SECONDS_MAX,
        step=0.1,
        mode=NumberSelectorMode.BOX,
        unit_of_measurement=UnitOfTime.SECONDS,
    )
)
SCHEMA = vol.Schema(
    {
        vol.Optional(CONF_FAST_INTERVAL): SECONDS,
        vol.Required(CONF_SCAN_INTERVAL): SECONDS,
        vol.Optional(CONF_SLOW_INTERVAL): SECONDS,
    }
)


def code_block(text: str) -> str:
    """Return a YAML text as a Markdown code block, its fence longer than any backticks in it."""
    longest = max((len(run) for run in re.findall(r"`+", text)), default=0)
    fence = "`" * max(3, longest + 1)
    return f"{fence}yaml\n{text.rstrip()}\n{fence}"


class PlcBridgeOptionsFlow(OptionsFlow):
    """Set how often the PLC is polled (the entry's update listener applies it); export it."""

    async def async_step_init(self, user_input: dict[str, Any] | None = None) -> ConfigFlowResult:
        """Offer the poll intervals and the export of the configuration."""
        return self.async_show_menu(step_id="init", menu_options=["polling", "export"])

    async def async_step_export(self, user_input: dict[str, Any] | None = None) -> ConfigFlowResult:
        """Show the PLC's configuration file to copy (secrets left out); change nothing."""
        if user_input is not None:
            return self.async_create_entry(data=dict(self.config_entry.options))
        return self.async_show_form(
            step_id="export",
            description_placeholders={
                "title": self.config_entry.title,
                "configuration": code_block(dump_config(self.config_entry)),
            },
        )

    async def async_step_polling(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Ask for the poll intervals; refuse those the vendor's pace or their order forbid."""
        data = self.config_entry.data
        client = client_class(data[CONF_VENDOR], data.get(CONF_OPTIONS, {}))
        plc = PlcConfig.from_entry(self.config_entry)
        minimums, points = plc.poll_minimums(client)
        options = self.config_entry.options
        current = plc.options.intervals
        errors: dict[str, str] = {}
        if user_input is not None:
            given = {key: float(value) for key, value in user_input.items() if key in INTERVALS}
            problems = plc.interval_problems(client, current | given)
            errors = {problem.field: problem.field_key for problem in problems}
            if not errors:
                return self.async_create_entry(data={**options, **given})
        current = unset(client, current, minimums)
        return self.async_show_form(
            step_id="polling",
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
