"""The expose subentry flow: a Home Assistant entity's state written to one PLC address.

One form, for a new expose and for editing one: the entity (and optionally an attribute), the
address and data type (checked by the vendor's parser, as a point's), the conversion, the
cooldown, the periodic resend, send-on-start, the value written while the entity is
unavailable, and whether it sends at all (turning on one pasted from a file runs the checks,
feedback included, now that its entities exist). Every check is `check_expose`'s.
"""

from __future__ import annotations

from functools import partial
from typing import Any

from homeassistant.config_entries import ConfigSubentryFlow, SubentryFlowResult
from homeassistant.const import CONF_ATTRIBUTE, CONF_ENTITY_ID
from homeassistant.helpers.selector import (
    BooleanSelector,
    EntitySelector,
    NumberSelector,
    NumberSelectorConfig,
    NumberSelectorMode,
    TextSelector,
)
import voluptuous as vol

from ..const import (
    CONF_ADDRESS,
    CONF_COOLDOWN,
    CONF_DATA_TYPE,
    CONF_DEFAULT,
    CONF_OFFSET,
    CONF_OPTIONS,
    CONF_RESEND,
    CONF_SCALE,
    CONF_SEND_ON_START,
    CONF_VALUE_MAP,
    CONF_VENDOR,
)
from ..model.expose import (
    CONF_SEND,
    DEFAULT_COOLDOWN,
    Checked,
    check_expose,
    entry_exposes,
    expose_title,
    feeds_back,
)
from ..model.plc_config import PlcConfig
from ..model.points import data_type_selector
from ..plc import PlcClient
from ..plc.vendors import client_class

_NUMBER = NumberSelector(NumberSelectorConfig(mode=NumberSelectorMode.BOX, step="any"))
RESEND_MAX = 86400.0
"""The longest periodic resend, in seconds (a day)."""


def _seconds(high: float) -> NumberSelector:
    """Return a field of seconds from 0 to `high`."""
    return NumberSelector(
        NumberSelectorConfig(
            min=0, max=high, step="any", mode=NumberSelectorMode.BOX, unit_of_measurement="s"
        )
    )


def expose_schema(client: type[PlcClient]) -> vol.Schema:
    """Return the expose form."""
    return vol.Schema(
        {
            vol.Required(CONF_ENTITY_ID): EntitySelector(),
            vol.Optional(CONF_ATTRIBUTE): TextSelector(),
            vol.Required(CONF_ADDRESS): TextSelector(),
            vol.Required(CONF_DATA_TYPE, default=client.data_types[0]): data_type_selector(client),
            vol.Required(CONF_SCALE, default=1.0): _NUMBER,
            vol.Required(CONF_OFFSET, default=0.0): _NUMBER,
            vol.Optional(CONF_VALUE_MAP): TextSelector(),
            vol.Required(CONF_COOLDOWN, default=DEFAULT_COOLDOWN): _seconds(3600.0),
            vol.Required(CONF_RESEND, default=0.0): _seconds(RESEND_MAX),
            vol.Required(CONF_SEND_ON_START, default=True): BooleanSelector(),
            vol.Required(CONF_SEND, default=True): BooleanSelector(),
            vol.Optional(CONF_DEFAULT): TextSelector(),
        }
    )


class ExposeSubentryFlowHandler(ConfigSubentryFlow):
    """Add or edit one expose of the PLC."""

    _asked: tuple[str, str] | None = None  # an attribute the entity lacked, told once

    @property
    def _client(self) -> type[PlcClient]:
        """The client class of the entry's PLC: its parser (for its options), types, checks."""
        data = self._get_entry().data
        return client_class(data[CONF_VENDOR], data.get(CONF_OPTIONS, {}))

    async def async_step_user(self, user_input: dict[str, Any] | None = None) -> SubentryFlowResult:
        """Show the empty form."""
        return await self.async_step_expose(user_input)

    async def async_step_reconfigure(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """Show the form filled in with the expose's settings."""
        return await self.async_step_expose(user_input)

    async def async_step_expose(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """Check the form; store the expose, or show the errors on their fields."""
        errors: dict[str, str] = {}
        placeholders = {"error": "", CONF_ADDRESS: ""}
        if user_input is not None:
            data, errors, placeholders = self._check(user_input)
            if not errors and (missing := self._missing_attribute(data)) is not None:
                errors = {CONF_ATTRIBUTE: "expose_attribute_missing"}
                placeholders |= missing
            if not errors:
                if self.source == "reconfigure":
                    return self.async_update_and_abort(
                        self._get_entry(),
                        self._get_reconfigure_subentry(),
                        title=expose_title(data),
                        data=data,
                    )
                return self.async_create_entry(title=expose_title(data), data=data)
        suggested = user_input
        if suggested is None and self.source == "reconfigure":
            suggested = dict(self._get_reconfigure_subentry().data)
        return self.async_show_form(
            step_id="expose",
            data_schema=self.add_suggested_values_to_schema(
                expose_schema(self._client), suggested or {}
            ),
            errors=errors,
            description_placeholders=placeholders,
        )

    def _check(self, values: dict[str, Any]) -> Checked:
        """Check the form through the one validation of an expose; its errors by field."""
        entry = self._get_entry()
        editing = self._reconfigure_subentry_id if self.source == "reconfigure" else None
        return check_expose(
            self._client,
            values,
            read_only=PlcConfig.from_entry(entry).read_only_points(),
            taken=[c.point for sid, c in entry_exposes(entry).items() if sid != editing],
            feeds_back=partial(feeds_back, self.hass, entry, editing=editing),
        )

    def _missing_attribute(self, data: dict[str, Any]) -> dict[str, str] | None:
        """Return what to tell when the entity has no such attribute now; None when it has.

        Some attributes come and go with the entity's state: the same form submitted again
        keeps the attribute as typed (nothing is written while the entity lacks it).
        """
        attribute = data.get(CONF_ATTRIBUTE)
        state = self.hass.states.get(data[CONF_ENTITY_ID])
        if not attribute or state is None or attribute in state.attributes:
            return None
        asked = (state.entity_id, str(attribute))
        if self._asked == asked:
            return None
        self._asked = asked
        names = ", ".join(sorted(state.attributes)) or "none"
        return {"entity": state.entity_id, "attribute": str(attribute), "attributes": names}
