"""The config flow's shared steps: a vendor's connection pages, the certificate, connect, store.

The pasted file, the DHCP discovery and reauthentication build on this one base (their
modules beside it); config_flow.py joins them into the flow Home Assistant looks up.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from homeassistant.config_entries import (
    SOURCE_RECONFIGURE,
    ConfigEntry,
    ConfigEntryState,
    ConfigFlow,
    ConfigFlowResult,
    ConfigSubentryFlow,
    SubentryFlowResult,
)
from homeassistant.const import CONF_HOST, CONF_PORT
from homeassistant.helpers.device_registry import format_mac
import voluptuous as vol

from ..const import (
    CONF_FINGERPRINT,
    CONF_OPTIONS,
    CONF_POINTS,
    CONF_TLS,
    CONF_VENDOR,
    LOGGER,
)
from ..model.plc_config import Connection, Problem, file_problems
from ..model.points import point_key
from ..model.vendor_fields import SECOND_PAGES, VENDOR_FIELDS
from ..plc import (
    BrowseItem,
    DeviceInfo,
    PlcClient,
    PlcError,
    Point,
    TlsMode,
)
from ..plc.http import fetch_fingerprint, format_fingerprint
from ..plc.vendors import client_class
from ..runtime.connection import create_client
from .connection_form import (
    connection_data,
    connection_schema,
    connection_step,
    error_for,
    fields_schema,
    form_values,
    on_form,
    problem_errors,
    refused_field,
    second_page,
    vendor_options,
)
from .flow_lists import async_point_words, menu_listing
from .vendor_steps import Input

INTEGRATION_NAME = "PLC Bridge"
CERTIFICATE_TIMEOUT = 10.0
"""Seconds to wait for the PLC's TLS handshake when fetching its certificate."""


def device_unique_id(device: DeviceInfo, data: Mapping[str, Any]) -> str:
    """Return the entry's unique id: the serial or MAC, else host:port for devices without."""
    if device.serial:
        return device.serial
    if device.mac:
        return format_mac(device.mac)
    return f"{data[CONF_HOST]}:{data[CONF_PORT]}"


def entry_title(device: DeviceInfo, host: str) -> str:
    """Return a new entry's title: the PLC's own name, else its model and host.

    Never the integration's name, which some PLCs report as their station name.
    """
    name = (device.name or "").strip()
    if name and name.casefold() != INTEGRATION_NAME.casefold():
        return name
    return f"{device.model} {host}"


class PlcFlowBase(ConfigFlow):
    """The steps every way into a PLC entry shares: connection pages, certificate, connect."""

    def __init__(self) -> None:
        """Start with nothing chosen and no certificate trusted."""
        self._vendor = ""
        self._data: dict[str, Any] = {}
        self._entered: dict[str, Any] = {}  # every value the pages took, suggested again
        self._trusted: set[str] = set()
        self._problem = ""  # the protocol layer's words for the last failure, shown in errors

    async def async_step_certificate(self, user_input: Input = None) -> ConfigFlowResult:
        """Show the certificate the PLC presents now; trusting it pins it."""
        fingerprint: str = self._data[CONF_FINGERPRINT]
        if user_input is not None:
            self._trusted.add(fingerprint)
            return await self._finish()
        return self.async_show_form(
            step_id="certificate",
            description_placeholders={
                CONF_HOST: self._data[CONF_HOST],
                CONF_PORT: str(self._data[CONF_PORT]),
                CONF_FINGERPRINT: format_fingerprint(fingerprint),
            },
        )

    async def _connection_step(self, user_input: Input = None) -> ConfigFlowResult:
        """Take a vendor's connection page; go on to its second page, if it has one.

        Options that name files (SoftPLC's client certificate and key) are resolved in the
        config folder first; then the model checks the connection the page describes
        (`Connection.problems`), each problem on its field, before anything is sent.
        """
        if user_input is None:
            return self._connection_form({})
        self._enter(self._connection_schema(), user_input)
        stored = self._data.get(CONF_OPTIONS)
        files, problems = await self.hass.async_add_executor_job(
            file_problems, self._vendor, self.hass.config.config_dir, user_input, stored or {}
        )
        if problems:
            return self._connection_form(self._errors_of(problems))
        client = client_class(self._vendor)
        self._data.update(connection_data(client, self._vendor, user_input | files, stored))
        if problems := list(Connection.from_data(self._data).address_problems()):
            return self._connection_form(self._errors_of(problems))
        if self._vendor in SECOND_PAGES:
            return self._second_form({})
        return await self._check_and_connect()

    def _errors_of(self, problems: Sequence[Problem]) -> dict[str, str]:
        """Return the form errors of the model's problems, each on its field; keep their words."""
        self._problem = problems[0].placeholders.get("problem", "")
        return problem_errors(problems)

    async def _second_page_step(self, user_input: Input = None) -> ConfigFlowResult:
        """Take the fields of the way chosen on the connection page, then connect."""
        if user_input is None:
            return self._second_form({})
        fields = second_page(self._vendor, self._data[CONF_OPTIONS])[1]
        self._enter(vol.Schema(fields_schema(fields)), user_input)
        self._data[CONF_OPTIONS] |= vendor_options(fields, user_input)
        return await self._check_and_connect()

    def _enter(self, schema: vol.Schema, user_input: Mapping[str, Any]) -> None:
        """Remember a page's values but secrets; a field left empty (not sent) forgets the older."""
        for marker in schema.schema:
            self._entered.pop(str(marker), None)
        secrets = {field.key for field in VENDOR_FIELDS.get(self._vendor, ()) if field.credential}
        self._entered.update({k: v for k, v in user_input.items() if k not in secrets})

    async def _check_and_connect(self) -> ConfigFlowResult:
        """Check the connection as the model does, fetch the certificate in pin mode, connect."""
        if problems := list(Connection.from_data(self._data).problems()):
            errors = self._errors_of(problems)
            field = next(iter(errors))
            if self._vendor in SECOND_PAGES and (field == "base" or field in self._second_fields()):
                return self._second_form(errors)
            return self._connection_form(errors)
        client = client_class(self._vendor)
        self._data[CONF_OPTIONS] = client.validate_options(self._data[CONF_OPTIONS])
        self._data[CONF_FINGERPRINT] = ""
        if self._data[CONF_TLS] == TlsMode.PIN:
            try:
                self._data[CONF_FINGERPRINT] = await fetch_fingerprint(
                    self._data[CONF_HOST], self._data[CONF_PORT], CERTIFICATE_TIMEOUT
                )
            except PlcError as err:
                self._problem = str(err)
                return self._connection_form(error_for(err))
            if self._data[CONF_FINGERPRINT] not in self._trusted:
                return await self.async_step_certificate()
        return await self._finish()

    async def _finish(self) -> ConfigFlowResult:
        """Connect with the gathered settings, then create or update the entry."""
        device, errors = await self._connect(self._data)
        if device is None and (field := refused_field(self._vendor, self._data, errors)):
            return self._second_form({field: "session_refused"})
        if device is None:
            return self._connection_form(errors)
        await self.async_set_unique_id(
            device_unique_id(device, self._data), raise_on_progress=False
        )
        if self.source != SOURCE_RECONFIGURE:
            self._abort_if_unique_id_configured()
            # Named after what the PLC reports: Home Assistant's own dialog then asks the device's
            # name and area (and renames the entity ids), so the name is asked once.
            return self._create_entry(entry_title(device, self._data[CONF_HOST]))
        entry = self._get_reconfigure_entry()
        if device.serial or device.mac:
            self._abort_if_unique_id_mismatch()
        elif self.unique_id != entry.unique_id:
            # Without a serial or MAC the address is the identity: it may move, not collide.
            self._abort_if_unique_id_configured()
        return self._store(entry, "reconfigure_successful", self._data, unique_id=self.unique_id)

    def _create_entry(self, title: str) -> ConfigFlowResult:
        """Create the entry of the PLC just checked, named as the PLC reports."""
        return self.async_create_entry(title=title, data=self._data)

    def _store(
        self, entry: ConfigEntry, reason: str, data: dict[str, Any], **changes: Any
    ) -> ConfigFlowResult:
        """Update the entry, have it set up again exactly once, and end the flow.

        By its update listener when loaded and changed; else here, as this flow's own login
        (S7-200 SMART: one session per user) may have ended Home Assistant's session.
        """
        # Asked before the update: the listener starts the reload at once (not loaded after).
        listener_reloads = entry.state is ConfigEntryState.LOADED and entry.data != data
        self.hass.config_entries.async_update_entry(entry, data=data, **changes)
        if not listener_reloads:
            self.hass.config_entries.async_schedule_reload(entry.entry_id)
        return self.async_abort(reason=reason)

    async def _connect(self, data: Mapping[str, Any]) -> tuple[DeviceInfo | None, dict[str, str]]:
        """Connect and log in once; return what the PLC says, or the form errors."""
        client = create_client(self.hass, data)
        self._problem = ""
        try:
            device = await client.connect()
            await client.check_access()  # what writes need is refused here, on the form
            return device, {}
        except PlcError as err:
            LOGGER.debug("Cannot connect to %s: %s", data[CONF_HOST], err)
            self._problem = str(err)
            return None, error_for(err, type(client))
        except Exception:
            LOGGER.exception("Unexpected error connecting to %s", data[CONF_HOST])
            return None, {"base": "unknown"}
        finally:
            await client.close()

    def _connection_schema(self) -> vol.Schema:
        """Return the vendor's connection page; a reconfigure keeps the credentials as they are."""
        return connection_schema(
            client_class(self._vendor),
            self._vendor,
            credentials=self.source != SOURCE_RECONFIGURE,
        )

    def _connection_form(self, errors: dict[str, str]) -> ConfigFlowResult:
        """Show the vendor's connection page with the values entered so far."""
        schema = self._connection_schema()
        return self._form(
            connection_step(self._vendor, reconfigure=self.source == SOURCE_RECONFIGURE),
            schema,
            errors,
        )

    def _second_fields(self) -> set[str]:
        """The keys of the second page's fields, for the way chosen on the connection page."""
        return {field.key for field in second_page(self._vendor, self._data[CONF_OPTIONS])[1]}

    def _second_form(self, errors: dict[str, str]) -> ConfigFlowResult:
        """Show the second page: the fields of the way chosen on the connection page."""
        step_id, fields = second_page(self._vendor, self._data[CONF_OPTIONS])
        return self._form(step_id, vol.Schema(fields_schema(fields)), errors)

    def _form(self, step_id: str, schema: vol.Schema, errors: dict[str, str]) -> ConfigFlowResult:
        """Show a connection page, suggesting what was entered or stored before."""
        return self.async_show_form(
            step_id=step_id,
            data_schema=self.add_suggested_values_to_schema(
                schema, self._entered | form_values(self._data)
            ),
            errors=on_form(errors, schema),
            description_placeholders={"problem": self._problem},
        )


class DeviceFlowBase(ConfigSubentryFlow):
    """What every page of the device flow shares: its state, the PLC's parser, taken points, menu.

    The machine page (machine_flow.py) and the pages of an entity of several points
    (composite_flow.py) build on it; subentry_flow.py joins them with the point pages.
    """

    def __init__(self) -> None:
        """Start with an unnamed device and no points."""
        self._name = ""
        self._area: str | None = None
        self._availability: dict[str, Any] = {}  # the availability fields, as stored
        self._points: dict[str, dict[str, Any]] = {}
        self._editing: str | None = None
        self._base: dict[str, Any] = {}
        self._published: list[BrowseItem] | None = None
        self._items: list[BrowseItem] = []
        self._ticked: list[str] = []
        self._confirmed = ""  # a pasted table whose assumed data types were shown
        self._composite: dict[str, Any] = {}  # the entity on its page: its kind, as checked
        self._edited: dict[str, str] = {}  # the edited entity's point ids by role

    @property
    def _client(self) -> type[PlcClient]:
        """The client class of the entry's PLC: its parser (for its options), types, browsing."""
        data = self._get_entry().data
        return client_class(data[CONF_VENDOR], data.get(CONF_OPTIONS, {}))

    def _taken(self) -> set[Point]:
        """Points of the PLC already used, outside the one being edited."""
        subentry_id = self._reconfigure_subentry_id if self.source == "reconfigure" else None
        taken = {
            point_key(data)
            for subentry in self._get_entry().subentries.values()
            if subentry.subentry_id != subentry_id
            for data in subentry.data.get(CONF_POINTS, {}).values()
        }
        taken |= {point_key(data) for pid, data in self._points.items() if not self._edits(pid)}
        return {self._normal(point) for point in taken}

    def _plc_points(self) -> list[dict[str, Any]]:
        """The stored data of the PLC's points, outside the one being edited."""
        subentry_id = self._reconfigure_subentry_id if self.source == "reconfigure" else None
        return [
            *(
                data
                for subentry in self._get_entry().subentries.values()
                if subentry.subentry_id != subentry_id
                for data in subentry.data.get(CONF_POINTS, {}).values()
            ),
            *(data for pid, data in self._points.items() if not self._edits(pid)),
        ]

    def _edits(self, point_id: str) -> bool:
        """True for a point being edited: the point's own, or a part of the entity edited."""
        return point_id == self._editing or point_id in self._edited.values()

    def _normal(self, point: Point) -> Point:
        """Return a stored point as the vendor spells it (a PLCnext path with its component)."""
        try:
            return self._client.validate_point(point)
        except PlcError:
            return point

    def _can_copy(self) -> bool:
        """True where the menu offers copies of the machine (machine_flow.py)."""
        return False

    async def async_step_menu(self, user_input: dict[str, Any] | None = None) -> SubentryFlowResult:
        """Show what can be done next, and the points so far."""
        options = ["point", "composite"]
        if self._client.can_browse and self._get_entry().state is ConfigEntryState.LOADED:
            options.append("browse")
        options.append("import_points")
        if self._points:
            options += ["edit", "remove"]
        options.append("device")
        if self._can_copy():
            options.append("copies")
        if self._points:
            options.append("save")
        return self.async_show_menu(
            step_id="menu",
            menu_options=options,
            description_placeholders={
                "name": self._name,
                "count": str(len(self._points)),
                "points": menu_listing(
                    self._points, self._client, await async_point_words(self.hass)
                ),
            },
        )
