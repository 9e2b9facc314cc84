"""Config flow of PLC Bridge: vendor, connection and certificate; reauth and reconfigure."""

from __future__ import annotations

from homeassistant.config_entries import (
    ConfigEntry,
    ConfigFlowResult,
    ConfigSubentryFlow,
)
from homeassistant.const import CONF_PASSWORD, CONF_USERNAME
from homeassistant.core import callback

from .const import (
    CONF_FINGERPRINT,
    CONF_VENDOR,
    DOMAIN,
    SUBENTRY_DEVICE,
    SUBENTRY_EXPOSE,
)
from .flows.config_file_flow import PASTE, ConfigFileSteps
from .flows.connection_form import (
    form_values,
    vendor_schema,
)
from .flows.discovery import DiscoveryFlow
from .flows.expose_flow import ExposeSubentryFlowHandler
from .flows.options_flow import PlcBridgeOptionsFlow
from .flows.reauth_flow import ReauthSteps
from .flows.subentry_flow import DeviceSubentryFlowHandler
from .flows.vendor_steps import Input, with_vendor_steps

VENDOR = "vendor"
"""The first page's choice of connecting to a PLC, and the step picking its family."""


@with_vendor_steps
class PlcBridgeConfigFlow(ConfigFileSteps, DiscoveryFlow, ReauthSteps, domain=DOMAIN):
    """Add a PLC: family (or a DHCP discovery, or a pasted file), connection, certificate.

    Each vendor's connection pages have step ids of their own, worded for its PLC family in
    strings.json; `with_vendor_steps` binds them to the shared steps of flows/base.py.
    """

    VERSION = 2
    MINOR_VERSION = 2  # 2.2: TecoApi and PLCnext times are durations (model/migration.py)

    @staticmethod
    @callback
    def async_get_options_flow(config_entry: ConfigEntry) -> PlcBridgeOptionsFlow:
        """Return the options flow (poll interval)."""
        return PlcBridgeOptionsFlow()

    @classmethod
    @callback
    def async_get_supported_subentry_types(
        cls, config_entry: ConfigEntry
    ) -> dict[str, type[ConfigSubentryFlow]]:
        """Return the subentry flows: a device of the plant, holding its points; an expose."""
        return {
            SUBENTRY_DEVICE: DeviceSubentryFlowHandler,
            SUBENTRY_EXPOSE: ExposeSubentryFlowHandler,
        }

    async def async_step_user(self, user_input: Input = None) -> ConfigFlowResult:
        """Offer the two ways in: connect to a PLC of a family, or paste an exported file."""
        return self.async_show_menu(step_id="user", menu_options=[VENDOR, PASTE])

    async def async_step_vendor(self, user_input: Input = None) -> ConfigFlowResult:
        """Pick the PLC family among those PLC Bridge implements."""
        if user_input is not None:
            self._vendor = user_input[CONF_VENDOR]
            self._data = {CONF_VENDOR: self._vendor, CONF_USERNAME: "", CONF_PASSWORD: ""}
            return self._connection_form({})
        return self.async_show_form(step_id=VENDOR, data_schema=vendor_schema())

    async def async_step_reconfigure(self, user_input: Input = None) -> ConfigFlowResult:
        """Show a configured PLC's connection page, filled in; its name stays as it is."""
        entry = self._get_reconfigure_entry()
        self._vendor = entry.data[CONF_VENDOR]
        self._data = dict(entry.data)
        self._entered = form_values(entry.data)
        self._trusted.add(entry.data.get(CONF_FINGERPRINT, ""))
        return self._connection_form({})
