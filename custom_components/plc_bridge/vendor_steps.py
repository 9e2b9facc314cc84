"""The vendors' pages of the config flow: a step id of its own for each, the same checks behind.

Home Assistant finds a step by its id (`async_step_<id>`), and strings.json words each page for
its PLC family alone: so every vendor has its own one-line steps here, leading to the flow's
shared ones (`_connection_step`, `_second_page_step`, `_reauth_options`).
"""

from __future__ import annotations

from typing import Any

from homeassistant.config_entries import ConfigFlowResult

type Input = dict[str, Any] | None
"""What a form step receives: the submitted values, or None to show the form."""


class VendorSteps:
    """The per-vendor steps; the config flow that mixes this in does the work."""

    async def _connection_step(self, user_input: Input) -> ConfigFlowResult:
        """Take a vendor's connection page (the config flow's)."""
        raise NotImplementedError

    async def _second_page_step(self, user_input: Input) -> ConfigFlowResult:
        """Take a vendor's second connection page (the config flow's)."""
        raise NotImplementedError

    async def _reauth_options(self, user_input: Input) -> ConfigFlowResult:
        """Take the vendor fields that authenticate again (the config flow's)."""
        raise NotImplementedError

    async def async_step_connection_s7_smart(self, user_input: Input = None) -> ConfigFlowResult:
        """Take the S7-200 SMART's address, certificate check and Web server user."""
        return await self._connection_step(user_input)

    async def async_step_connection_tecomat(self, user_input: Input = None) -> ConfigFlowResult:
        """Take the Tecomat's address, certificate check, TecoApi user and clock variable."""
        return await self._connection_step(user_input)

    async def async_step_connection_plcnext(self, user_input: Input = None) -> ConfigFlowResult:
        """Take the PLCnext Control's address, certificate check, user and clock variable."""
        return await self._connection_step(user_input)

    async def async_step_connection_softplc(self, user_input: Input = None) -> ConfigFlowResult:
        """Take the SoftPLC's address, certificate check and client certificate for writes."""
        return await self._connection_step(user_input)

    async def async_step_connection_s7(self, user_input: Input = None) -> ConfigFlowResult:
        """Take the S7 CPU's address, family and way to connect (rack/slot or TSAPs)."""
        return await self._connection_step(user_input)

    async def async_step_reconfigure_s7_smart(self, user_input: Input = None) -> ConfigFlowResult:
        """Take a configured S7-200 SMART's new address or certificate check."""
        return await self._connection_step(user_input)

    async def async_step_reconfigure_tecomat(self, user_input: Input = None) -> ConfigFlowResult:
        """Take a configured Tecomat's new address, certificate check or TecoApi settings."""
        return await self._connection_step(user_input)

    async def async_step_reconfigure_plcnext(self, user_input: Input = None) -> ConfigFlowResult:
        """Take a configured PLCnext Control's new address, certificate check or clock variable."""
        return await self._connection_step(user_input)

    async def async_step_reconfigure_softplc(self, user_input: Input = None) -> ConfigFlowResult:
        """Take a configured SoftPLC's new address, certificate check or client certificate."""
        return await self._connection_step(user_input)

    async def async_step_reconfigure_s7(self, user_input: Input = None) -> ConfigFlowResult:
        """Take a configured S7 CPU's new address, family or way to connect."""
        return await self._connection_step(user_input)

    async def async_step_s7_rack_slot(self, user_input: Input = None) -> ConfigFlowResult:
        """Take the S7 CPU's rack and slot."""
        return await self._second_page_step(user_input)

    async def async_step_s7_tsap(self, user_input: Input = None) -> ConfigFlowResult:
        """Take the TSAPs of the S7 connection (S7-200 with a CP 243-1, LOGO!)."""
        return await self._second_page_step(user_input)

    async def async_step_reauth_softplc(self, user_input: Input = None) -> ConfigFlowResult:
        """Take the client certificate and key a SoftPLC trusts now; check them before storing."""
        return await self._reauth_options(user_input)
