"""The expose subentry flow: a Home Assistant entity's state written to one PLC address.

One form, for a new expose and for editing one: the entity (and optionally an attribute), the
address and data type (checked by the vendor's parser, as a point's), the conversion, the
cooldown, the periodic resend, send-on-start and the value written while the entity is
unavailable.
"""

from __future__ import annotations

import re
from typing import Any

from homeassistant.config_entries import ConfigSubentryFlow, SubentryFlowResult
from homeassistant.const import CONF_ATTRIBUTE, CONF_ENTITY_ID
from homeassistant.exceptions import HomeAssistantError
from homeassistant.helpers import entity_registry as er
from homeassistant.helpers.selector import (
    BooleanSelector,
    EntitySelector,
    NumberSelector,
    NumberSelectorConfig,
    NumberSelectorMode,
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
    TextSelector,
)
import voluptuous as vol

from .composite import group_key
from .const import (
    CONF_ADDRESS,
    CONF_COOLDOWN,
    CONF_DATA_TYPE,
    CONF_DEFAULT,
    CONF_ENTITY,
    CONF_OFFSET,
    CONF_RESEND,
    CONF_SCALE,
    CONF_SEND_ON_START,
    CONF_VALUE_MAP,
    CONF_VENDOR,
)
from .conversion import InvalidPairs
from .expose_config import (
    DEFAULT_COOLDOWN,
    SENDABLE,
    entry_exposes,
    expose_config,
    expose_title,
    format_state_map,
    parse_state_map,
)
from .plc import PlcAddressError, PlcClient, PlcError, Point
from .plc.vendors import client_class
from .points import PointConfig, entry_points
from .write_guard import WriteGuard

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
            vol.Required(CONF_DATA_TYPE, default=client.data_types[0]): SelectSelector(
                SelectSelectorConfig(
                    options=list(client.data_types),
                    translation_key=CONF_DATA_TYPE,
                    mode=SelectSelectorMode.DROPDOWN,
                    custom_value=True,
                )
            ),
            vol.Required(CONF_SCALE, default=1.0): _NUMBER,
            vol.Required(CONF_OFFSET, default=0.0): _NUMBER,
            vol.Optional(CONF_VALUE_MAP): TextSelector(),
            vol.Required(CONF_COOLDOWN, default=DEFAULT_COOLDOWN): _seconds(3600.0),
            vol.Required(CONF_RESEND, default=0.0): _seconds(RESEND_MAX),
            vol.Required(CONF_SEND_ON_START, default=True): BooleanSelector(),
            vol.Optional(CONF_DEFAULT): TextSelector(),
        }
    )


def entity_key(config: PointConfig) -> str:
    """Return the end of the unique id of the entity that shows a point (its entity's key)."""
    return str(config.data.get(CONF_ENTITY) or config.point_id)


class ExposeSubentryFlowHandler(ConfigSubentryFlow):
    """Add or edit one expose of the PLC."""

    _asked: tuple[str, str] | None = None  # an attribute the entity lacked, told once

    @property
    def _client(self) -> type[PlcClient]:
        """The client class of the entry's vendor: its parser, data types and value checks."""
        return client_class(self._get_entry().data[CONF_VENDOR])

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

    def _check(
        self, values: dict[str, Any]
    ) -> tuple[dict[str, Any], dict[str, str], dict[str, str]]:
        """Check the form; return the data to store, the errors by field and their words."""
        client = self._client
        placeholders = {"error": "", CONF_ADDRESS: str(values.get(CONF_ADDRESS, ""))}
        try:
            point = client.validate_point(
                Point(str(values[CONF_ADDRESS]).strip(), str(values[CONF_DATA_TYPE]).strip())
            )
        except PlcAddressError as err:
            return {}, {CONF_ADDRESS: "invalid_address"}, placeholders | {"error": str(err)}
        placeholders[CONF_ADDRESS] = point.address
        errors: dict[str, str] = {}
        if client.value_kind(point) not in SENDABLE:
            errors[CONF_DATA_TYPE] = "expose_data_type"
        elif error := self._address_error(client, point):
            errors[CONF_ADDRESS] = error
        elif self._feeds_back(client, point, str(values[CONF_ENTITY_ID])):
            errors[CONF_ADDRESS] = "expose_feeds_back"
        data: dict[str, Any] = {
            CONF_ENTITY_ID: str(values[CONF_ENTITY_ID]),
            CONF_ADDRESS: point.address,
            CONF_DATA_TYPE: point.data_type,
            CONF_SCALE: float(values.get(CONF_SCALE, 1.0)),
            CONF_OFFSET: float(values.get(CONF_OFFSET, 0.0)),
            CONF_COOLDOWN: float(values.get(CONF_COOLDOWN, DEFAULT_COOLDOWN)),
            CONF_RESEND: float(values.get(CONF_RESEND, 0.0)),
            CONF_SEND_ON_START: bool(values.get(CONF_SEND_ON_START, True)),
        }
        if attribute := str(values.get(CONF_ATTRIBUTE) or "").strip():
            data[CONF_ATTRIBUTE] = attribute
        if data[CONF_SCALE] == 0:
            errors[CONF_SCALE] = "scale_zero"
        if text := str(values.get(CONF_VALUE_MAP) or "").strip():
            try:
                data[CONF_VALUE_MAP] = format_state_map(parse_state_map(text))
            except InvalidPairs as err:
                errors[CONF_VALUE_MAP] = err.key
                placeholders["pair"] = err.text
        if (default := str(values.get(CONF_DEFAULT) or "").strip()) and not errors:
            data[CONF_DEFAULT] = default
            try:
                expose_config("", "", data).plc_value(client, default)
            except PlcError as err:
                errors[CONF_DEFAULT] = "invalid_default"
                placeholders["error"] = str(err)
        return data, errors, placeholders

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
        names = ", ".join(f"`{name}`" for name in sorted(state.attributes)) or "none"
        return {"entity": state.entity_id, "attribute": str(attribute), "attributes": names}

    def _feeds_back(self, client: type[PlcClient], point: Point, entity_id: str) -> bool:
        """True when the entity is one of this PLC's and reads the address itself.

        Its value would come back converted at each change (a scale runs away), never settling.
        """
        registered = er.async_get(self.hass).async_get(entity_id)
        entry = self._get_entry()
        if registered is None or registered.config_entry_id != entry.entry_id:
            return False
        configs = entry_points(entry).values()
        tail = re.sub(r"_bit\d+$", "", registered.unique_id)  # an alarm word's bit: the word
        keys = {group_key(c) or c.point_id for c in configs if tail.endswith(f"_{entity_key(c)}")}
        shown = [c.point for c in configs if (group_key(c) or c.point_id) in keys]
        try:
            WriteGuard(client, shown).check(point)
        except HomeAssistantError:
            return True
        return False

    def _address_error(self, client: type[PlcClient], point: Point) -> str | None:
        """Return why no expose may write the address, if none may."""
        if not client.address_writable(point):
            return "address_not_writable"
        entry = self._get_entry()
        points = entry_points(entry).values()
        guard = WriteGuard(client, [config.point for config in points if config.read_only])
        try:
            guard.check(point)
        except HomeAssistantError:
            return "expose_read_only"
        editing = self._reconfigure_subentry_id if self.source == "reconfigure" else None
        # Another expose's address, under any data type or overlapping it, as the guard sees one.
        others = [other.point for sid, other in entry_exposes(entry).items() if sid != editing]
        try:
            WriteGuard(client, others).check(point)
        except HomeAssistantError:
            return "already_configured"
        return None
