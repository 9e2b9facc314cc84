"""Repair flows Home Assistant asks for: trust a replaced certificate, or acknowledge."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from homeassistant.components.repairs import ConfirmRepairFlow, RepairsFlow
from homeassistant.config_entries import ConfigEntryState
from homeassistant.const import CONF_HOST, CONF_PORT
from homeassistant.core import HomeAssistant
import voluptuous as vol

from .const import CONF_FINGERPRINT
from .plc import PlcError
from .plc.http import fetch_fingerprint, format_fingerprint
from .runtime.issues import CERTIFICATE_CHANGED

if TYPE_CHECKING:  # named since Home Assistant 2026.10; only annotations use it
    from homeassistant.components.repairs import RepairsFlowResult


class CertificateRepairFlow(RepairsFlow):
    """Show the certificate the PLC presents now; trusting it pins it and sets the entry up."""

    def __init__(self, entry_id: str) -> None:
        """Remember the entry whose pinned certificate no longer matches."""
        self._entry_id = entry_id
        self._fingerprint = ""

    async def async_step_init(self, user_input: dict[str, Any] | None = None) -> RepairsFlowResult:
        """Start with the certificate check."""
        return await self.async_step_confirm()

    async def async_step_confirm(
        self, user_input: dict[str, Any] | None = None
    ) -> RepairsFlowResult:
        """Fetch and show the new fingerprint; pin exactly the one shown once confirmed."""
        entry = self.hass.config_entries.async_get_entry(self._entry_id)
        if entry is None:
            return self.async_abort(reason="entry_removed")
        if user_input is not None:
            loaded = entry.state is ConfigEntryState.LOADED  # before the listener reloads it
            self.hass.config_entries.async_update_entry(
                entry, data={**entry.data, CONF_FINGERPRINT: self._fingerprint}
            )
            if not loaded:
                # A loaded entry reloads through its update listener; one waiting to retry not.
                self.hass.config_entries.async_schedule_reload(entry.entry_id)
            return self.async_create_entry(data={})
        try:
            self._fingerprint = await fetch_fingerprint(
                entry.data[CONF_HOST], int(entry.data[CONF_PORT])
            )
        except PlcError as err:
            return self.async_abort(
                reason="cannot_connect", description_placeholders={"error": str(err)}
            )
        return self.async_show_form(
            step_id="confirm",
            data_schema=vol.Schema({}),
            description_placeholders={
                "title": entry.title,
                "host": str(entry.data[CONF_HOST]),
                "port": str(entry.data[CONF_PORT]),
                "fingerprint": format_fingerprint(self._fingerprint),
            },
        )


async def async_create_fix_flow(
    hass: HomeAssistant, issue_id: str, data: dict[str, str | int | float | None] | None
) -> RepairsFlow:
    """Return the fix flow of an issue: trust the new certificate, or just acknowledge."""
    if issue_id.startswith(CERTIFICATE_CHANGED) and data and isinstance(data["entry_id"], str):
        return CertificateRepairFlow(data["entry_id"])
    return ConfirmRepairFlow()
