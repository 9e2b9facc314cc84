"""DHCP discovery: a PLC maker's MAC seen, its interfaces probed, offered only where one answers.

Home Assistant's DHCP watcher also reads the ARP table, so a PLC with a static address is seen
too. A known PLC seen at a new address has its entry's host updated instead.
"""

from __future__ import annotations

import asyncio
from typing import Any

from homeassistant.config_entries import ConfigEntry, ConfigFlowResult
from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_PORT, CONF_USERNAME
from homeassistant.core import HomeAssistant, callback
from homeassistant.helpers import device_registry as dr
from homeassistant.helpers.aiohttp_client import async_get_clientsession
from homeassistant.helpers.service_info.dhcp import DhcpServiceInfo
from homeassistant.util.network import is_ip_address
import voluptuous as vol

from ..const import CONF_MAC, CONF_VENDOR, DOMAIN
from ..plc.vendors import client_class, implemented, probe_of
from .base import PlcFlowBase
from .connection_form import vendor_schema
from .mac_prefixes import Family, family_of

PROBE_TIMEOUT = 3.0
"""Seconds a probe of one interface may take (the probes of one host run at once)."""

PROBE_PORTS: dict[str, int] = {
    vendor: client_class(vendor).default_port for vendor in implemented()
}
"""Where each vendor's interface is probed: the port its connection page suggests."""


async def answering(
    hass: HomeAssistant, host: str, vendors: tuple[str, ...]
) -> dict[str, dict[str, Any]]:
    """Return the vendors whose interface answers at host, in the order given.

    Each comes with the connection options it answered with (an S7 CPU's slot).
    """
    session = async_get_clientsession(hass)

    async def answers(vendor: str) -> dict[str, Any] | None:
        probe = probe_of(vendor)
        if probe is None:
            return None
        return await probe(host, PROBE_PORTS[vendor], session, PROBE_TIMEOUT)

    found = await asyncio.gather(*(answers(vendor) for vendor in vendors))
    return {
        vendor: options
        for vendor, options in zip(vendors, found, strict=True)
        if options is not None
    }


@callback
def entry_of_mac(hass: HomeAssistant, mac: str) -> ConfigEntry | None:
    """Return the entry of the PLC with this MAC: keyed by it, noted at discovery, or by device."""
    entries = hass.config_entries.async_entries(DOMAIN, include_ignore=False)
    for entry in entries:
        if mac in (entry.unique_id, entry.data.get(CONF_MAC)):
            return entry
    registry = dr.async_get(hass)
    connection = (dr.CONNECTION_NETWORK_MAC, mac)
    for entry in entries:
        devices = dr.async_entries_for_config_entry(registry, entry.entry_id)
        if any(connection in device.connections for device in devices):
            return entry
    return None


class DiscoveryFlow(PlcFlowBase):
    """The config flow's DHCP steps; the vendor's connection page and checks follow as usual."""

    _found: dict[str, dict[str, Any]]  # the vendors that answered, with what they answered
    _family: Family
    _host: str

    async def async_step_dhcp(self, discovery_info: DhcpServiceInfo) -> ConfigFlowResult:
        """Take a DHCP sighting: move a known PLC, else probe its maker's interfaces and offer."""
        mac = dr.format_mac(discovery_info.macaddress)
        host = discovery_info.ip
        if (entry := entry_of_mac(self.hass, mac)) is not None and entry.unique_id is not None:
            await self.async_set_unique_id(entry.unique_id, raise_on_progress=False)
            if not is_ip_address(str(entry.data.get(CONF_HOST, ""))):
                # Set up by name: the name follows the PLC, and a certificate checked against
                # it would fail for the address. One waiting to retry is reloaded.
                self._abort_if_unique_id_configured()
            port = entry.data.get(CONF_PORT)
            if entry.unique_id == f"{entry.data.get(CONF_HOST)}:{port}":
                # Known by its address (it reports no serial): the identity moves with it.
                self.hass.config_entries.async_update_entry(entry, unique_id=f"{host}:{port}")
                await self.async_set_unique_id(entry.unique_id, raise_on_progress=False)
            # A flow reloading an entry that has an update listener is logged (2026.10) and an
            # error from Home Assistant 2026.12: ours (`async_update_entry`) reloads a loaded
            # entry for its new host, so reload_on_update=False. One waiting to retry its setup
            # has no listener yet; Home Assistant reloads it, as for any discovery.
            self._abort_if_unique_id_configured(updates={CONF_HOST: host}, reload_on_update=False)
        self._async_abort_entries_match({CONF_HOST: host})  # configured there: nothing to probe
        await self.async_set_unique_id(mac)
        self._abort_if_unique_id_configured()  # a discovery of this PLC the user ignored
        if (family := family_of(mac)) is None:
            return self.async_abort(reason="not_a_plc_maker")
        self._family, self._host = family, host
        self.context["title_placeholders"] = {"family": family.name, "host": host}
        self._found = await answering(self.hass, host, family.vendors)
        if not self._found:
            return self.async_abort(
                reason="no_interface",
                description_placeholders={"family": family.name, "host": host},
            )
        return await self.async_step_discovery_confirm()

    async def async_step_discovery_confirm(
        self, user_input: dict[str, Any] | None = None
    ) -> ConfigFlowResult:
        """Name the PLC found; where several of its interfaces answered, the user picks one."""
        if user_input is not None:
            self._vendor = user_input.get(CONF_VENDOR, next(iter(self._found)))
            self._data = {
                CONF_VENDOR: self._vendor,
                CONF_USERNAME: "",
                CONF_PASSWORD: "",
                CONF_MAC: self.unique_id,
            }
            self._entered = {
                CONF_HOST: self._host,
                CONF_PORT: PROBE_PORTS[self._vendor],
                **self._found[self._vendor],  # an S7 CPU's slot, on the rack/slot page
            }
            return self._connection_form({})
        return self.async_show_form(
            step_id="discovery_confirm",
            data_schema=vendor_schema(vendors=list(self._found))
            if len(self._found) > 1
            else vol.Schema({}),
            description_placeholders={"family": self._family.name, "host": self._host},
        )
