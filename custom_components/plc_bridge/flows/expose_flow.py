"""The expose subentry flow: a Home Assistant entity's state written to one PLC address.

Two pages, for a new expose and for editing one. The first picks the entity; the second offers
its attributes to pick from (left out when it has none worth sending) beside the address and
data type (checked by the vendor's parser, as a point's), the conversion, the cooldown, the
periodic resend, send-on-start, the value written while the entity is unavailable, and whether
it sends at all (turning on one pasted from a file runs the checks, feedback included, now that
its entities exist). Every check is `check_expose`'s.
"""

from __future__ import annotations

from functools import partial
from typing import Any

from homeassistant.config_entries import ConfigSubentryFlow, SubentryFlowResult
from homeassistant.const import CONF_ATTRIBUTE, CONF_ENTITY_ID
from homeassistant.core import State
from homeassistant.helpers.selector import (
    AttributeSelector,
    AttributeSelectorConfig,
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
DESCRIPTIVE_ATTRIBUTES = (
    "assumed_state",
    "attribution",
    "device_class",
    "editable",
    "entity_picture",
    "friendly_name",
    "icon",
    "restored",
    "state_class",
    "supported_features",
    "unit_of_measurement",
)
"""Attributes that describe the entity rather than measure anything: not offered to send."""


def _seconds(high: float) -> NumberSelector:
    """Return a field of seconds from 0 to `high`."""
    return NumberSelector(
        NumberSelectorConfig(
            min=0, max=high, step="any", mode=NumberSelectorMode.BOX, unit_of_measurement="s"
        )
    )


ENTITY_SCHEMA = vol.Schema({vol.Required(CONF_ENTITY_ID): EntitySelector()})
"""The first page: the entity whose state (or one of its attributes) is sent."""


def sendable_attributes(state: State | None) -> list[str]:
    """Return the attributes of an entity's state offered to send, in their order."""
    if state is None:
        return []
    return [name for name in state.attributes if name not in DESCRIPTIVE_ATTRIBUTES]


def expose_schema(client: type[PlcClient], entity_id: str, *, attribute: bool) -> vol.Schema:
    """Return the second page: the attribute of `entity_id` (when asked), address and the rest."""
    fields: dict[vol.Marker, Any] = {}
    if attribute:
        fields[vol.Optional(CONF_ATTRIBUTE)] = AttributeSelector(
            AttributeSelectorConfig(
                entity_id=entity_id, hide_attributes=list(DESCRIPTIVE_ATTRIBUTES)
            )
        )
    return vol.Schema(
        fields
        | {
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
    _entity_id: str = ""

    @property
    def _client(self) -> type[PlcClient]:
        """The client class of the entry's PLC: its parser (for its options), types, checks."""
        data = self._get_entry().data
        return client_class(data[CONF_VENDOR], data.get(CONF_OPTIONS, {}))

    async def async_step_user(self, user_input: dict[str, Any] | None = None) -> SubentryFlowResult:
        """Ask the entity."""
        return await self.async_step_entity(user_input)

    async def async_step_reconfigure(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """Ask the entity, the stored one suggested."""
        return await self.async_step_entity(user_input)

    async def async_step_entity(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """Take the entity; go on to its attribute, address and conversion."""
        if user_input is not None:
            self._entity_id = str(user_input[CONF_ENTITY_ID])
            return await self.async_step_expose()
        return self.async_show_form(
            step_id="entity",
            data_schema=self.add_suggested_values_to_schema(ENTITY_SCHEMA, self._stored()),
        )

    async def async_step_expose(
        self, user_input: dict[str, Any] | None = None
    ) -> SubentryFlowResult:
        """Check the second page; store the expose, or show the errors on their fields."""
        errors: dict[str, str] = {}
        placeholders = {"error": "", CONF_ADDRESS: ""}
        if user_input is not None:
            data, errors, placeholders = self._check(user_input | {CONF_ENTITY_ID: self._entity_id})
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
        stored = self._stored()
        if stored.get(CONF_ENTITY_ID) != self._entity_id:
            stored.pop(CONF_ATTRIBUTE, None)
        suggested = stored if user_input is None else user_input
        attribute = bool(
            sendable_attributes(self.hass.states.get(self._entity_id))
            or stored.get(CONF_ATTRIBUTE)
            or suggested.get(CONF_ATTRIBUTE)
        )
        return self.async_show_form(
            step_id="expose",
            data_schema=self.add_suggested_values_to_schema(
                expose_schema(self._client, self._entity_id, attribute=attribute), suggested
            ),
            errors=errors,
            description_placeholders=placeholders,
        )

    def _stored(self) -> dict[str, Any]:
        """Return the settings of the expose being edited; none for a new one."""
        if self.source != "reconfigure":
            return {}
        return dict(self._get_reconfigure_subentry().data)

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
