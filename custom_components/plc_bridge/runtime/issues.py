"""Repair issues: an unchecked TLS link, a replaced certificate, a shared PLC user, lost points.

And outputs that cannot be released (raised and cleared by outputs.py).
"""

from __future__ import annotations

from collections.abc import Collection
from typing import Any

from homeassistant.config_entries import ConfigEntry
from homeassistant.const import CONF_HOST
from homeassistant.core import HomeAssistant, callback
from homeassistant.helpers import issue_registry as ir

from ..const import CONF_OPTIONS, CONF_TLS, DOMAIN
from ..plc import TlsMode

TLS_OFF = "tls_off"
CERTIFICATE_CHANGED = "certificate_changed"
SESSION_CONFLICT = "session_conflict"
PLAIN_PASSWORD = "plain_password"
"""Basic authentication over plain HTTP: the password crosses the network readable."""
TIMES_IN_SECONDS = "times_in_seconds"
"""Raised once by the migration to 2.2 (TecoApi, PLCnext): kept until the user dismisses it."""
ISSUES = (TLS_OFF, CERTIFICATE_CHANGED, SESSION_CONFLICT, PLAIN_PASSWORD, TIMES_IN_SECONDS)
UNKNOWN_ADDRESS = "unknown_address"
"""One issue per point whose address the PLC does not know (typically a renamed variable)."""
EXPOSE_FAILED = "expose_failed"
"""One issue per expose whose writes keep failing."""
PULSE_FAILED = "pulse_failed"
"""One issue per pulsed output whose off is not written yet (outputs.py)."""
COMMAND_NOT_RELEASED = "command_not_released"
"""One issue per level command of a cover or valve whose off is not written yet."""
FEEDBACK_TIMEOUT = "feedback_timeout"
"""One issue per entity whose state did not follow its command in time (supervision.py)."""


def issue_id(entry: ConfigEntry[Any], key: str) -> str:
    """Return the id of an entry's issue: one of each kind per PLC."""
    return f"{key}_{entry.entry_id}"


@callback
def async_raise_issue(hass: HomeAssistant, entry: ConfigEntry[Any], key: str) -> None:
    """Create (or keep) an issue of the entry; a changed certificate is fixable here."""
    ir.async_create_issue(
        hass,
        DOMAIN,
        issue_id(entry, key),
        is_fixable=key == CERTIFICATE_CHANGED,
        severity=ir.IssueSeverity.ERROR if key == CERTIFICATE_CHANGED else ir.IssueSeverity.WARNING,
        is_persistent=key == TIMES_IN_SECONDS,  # the others are raised again by each setup
        translation_key=key,
        translation_placeholders={"title": entry.title, "host": str(entry.data[CONF_HOST])},
        data={"entry_id": entry.entry_id},
    )


@callback
def async_clear_issue(hass: HomeAssistant, entry: ConfigEntry[Any], key: str) -> None:
    """Delete an issue of the entry, if it is there."""
    ir.async_delete_issue(hass, DOMAIN, issue_id(entry, key))


def point_issue_id(entry: ConfigEntry, point_id: str) -> str:
    """Return the id of a point's unknown-address issue."""
    return f"{UNKNOWN_ADDRESS}_{entry.entry_id}_{point_id}"


def expose_issue_id(entry: ConfigEntry, subentry_id: str) -> str:
    """Return the id of an expose's issue."""
    return f"{EXPOSE_FAILED}_{entry.entry_id}_{subentry_id}"


@callback
def _async_raise_item_issue(
    hass: HomeAssistant,
    entry: ConfigEntry,
    kind: str,
    item: tuple[str, str],
    placeholders: dict[str, str],
) -> None:
    """Create (or update) the issue `kind` of one item of the entry (a point, an expose)."""
    key, item_id = item
    ir.async_create_issue(
        hass,
        DOMAIN,
        f"{kind}_{entry.entry_id}_{item_id}",
        is_fixable=False,
        severity=ir.IssueSeverity.WARNING,
        translation_key=kind,
        translation_placeholders={"title": entry.title, **placeholders},
        data={"entry_id": entry.entry_id, key: item_id},
    )


@callback
def _async_item_issues(hass: HomeAssistant, entry: ConfigEntry, kind: str) -> set[str]:
    """Return the ids of the entry's items that have an issue `kind`."""
    prefix = f"{kind}_{entry.entry_id}_"
    return {
        issue[len(prefix) :]
        for domain, issue in ir.async_get(hass).issues
        if domain == DOMAIN and issue.startswith(prefix)
    }


@callback
def async_raise_point_issue(
    hass: HomeAssistant,
    entry: ConfigEntry[Any],
    point_id: str,
    *,
    name: str,
    address: str,
    error: str,
) -> None:
    """Create (or update) the issue of a point the PLC does not know."""
    placeholders = {"point": name, "address": address, "error": error}
    _async_raise_item_issue(hass, entry, UNKNOWN_ADDRESS, ("point_id", point_id), placeholders)


@callback
def async_clear_point_issue(hass: HomeAssistant, entry: ConfigEntry[Any], point_id: str) -> None:
    """Delete a point's issue, if it is there."""
    ir.async_delete_issue(hass, DOMAIN, point_issue_id(entry, point_id))


@callback
def async_point_issues(hass: HomeAssistant, entry: ConfigEntry[Any]) -> set[str]:
    """Return the ids of the entry's points that have an unknown-address issue."""
    return _async_item_issues(hass, entry, UNKNOWN_ADDRESS)


@callback
def async_clear_point_issues(
    hass: HomeAssistant, entry: ConfigEntry, keep: Collection[str] = ()
) -> None:
    """Delete the point issues of an entry, except those of the point ids in `keep`."""
    for point_id in _async_item_issues(hass, entry, UNKNOWN_ADDRESS) - set(keep):
        ir.async_delete_issue(hass, DOMAIN, point_issue_id(entry, point_id))


@callback
def async_raise_expose_issue(
    hass: HomeAssistant,
    entry: ConfigEntry[Any],
    subentry_id: str,
    *,
    name: str,
    address: str,
    error: str,
) -> None:
    """Create (or update) the issue of an expose whose writes keep failing."""
    placeholders = {"expose": name, "address": address, "error": error}
    _async_raise_item_issue(hass, entry, EXPOSE_FAILED, ("subentry_id", subentry_id), placeholders)


@callback
def async_clear_expose_issues(
    hass: HomeAssistant, entry: ConfigEntry, keep: Collection[str] = ()
) -> None:
    """Delete the expose issues of an entry, except those of the subentry ids in `keep`."""
    for subentry_id in _async_item_issues(hass, entry, EXPOSE_FAILED) - set(keep):
        ir.async_delete_issue(hass, DOMAIN, expose_issue_id(entry, subentry_id))


@callback
def async_check_tls(hass: HomeAssistant, entry: ConfigEntry[Any]) -> None:
    """Raise the issues of a link that leaks: no certificate check, a readable password."""
    if entry.data.get(CONF_TLS) == TlsMode.OFF:
        async_raise_issue(hass, entry, TLS_OFF)
    else:
        async_clear_issue(hass, entry, TLS_OFF)
    basic = str(entry.data.get(CONF_OPTIONS, {}).get("auth", "")).strip().lower() == "basic"
    if basic and entry.data.get(CONF_TLS, TlsMode.NONE) == TlsMode.NONE:
        async_raise_issue(hass, entry, PLAIN_PASSWORD)
    else:
        async_clear_issue(hass, entry, PLAIN_PASSWORD)


@callback
def async_clear_all(hass: HomeAssistant, entry: ConfigEntry) -> None:
    """Delete every issue of a removed PLC, its points' too."""
    for key in ISSUES:
        async_clear_issue(hass, entry, key)
    async_clear_point_issues(hass, entry)
    async_clear_expose_issues(hass, entry)
    for kind in (PULSE_FAILED, COMMAND_NOT_RELEASED, FEEDBACK_TIMEOUT):
        for key in _async_item_issues(hass, entry, kind):
            ir.async_delete_issue(hass, DOMAIN, f"{kind}_{entry.entry_id}_{key}")
