"""Fixtures of the flow tests: a fake browsing vendor, and the texts a form must have.

Their simulator and its entry (`flow_sim`, `flow_entry`) are the harness's (tests/harness.py).
"""

from __future__ import annotations

from collections.abc import Generator, Mapping, Sequence
from datetime import datetime
import json
from pathlib import Path
import re
from typing import Any, ClassVar
from unittest.mock import AsyncMock, patch

from homeassistant.config_entries import SOURCE_USER
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType, section as form_section
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.config_flow import PlcBridgeConfigFlow
from custom_components.plc_bridge.const import (
    SUBENTRY_DEVICE,
)
from custom_components.plc_bridge.model.kinds import KINDS
from custom_components.plc_bridge.plc import (
    BrowseItem,
    DeviceInfo,
    PlcAddressError,
    PlcClient,
    Point,
    PointResult,
    ReadResult,
    Value,
    vendors,
)

STRINGS = json.loads(
    (Path(__file__).parents[2] / "custom_components/plc_bridge/strings.json").read_text()
)
FAKE_VENDOR = "plcnext"
"""The vendor key FakeClient stands in for, in the tests that ask for it: a real key, so that its
connection forms have their strings; the real PLCnext client is tested on its own simulator."""


@pytest.fixture
def mock_setup_entry() -> Generator[AsyncMock]:
    """Keep the integration from setting up: for tests of the flow alone."""
    with patch("custom_components.plc_bridge.async_setup_entry", return_value=True) as mock:
        yield mock


class FakeClient(PlcClient):
    """A browsing vendor without TLS or credentials that reports a serial number."""

    vendor: ClassVar[str] = FAKE_VENDOR
    default_port: ClassVar[int] = 8080
    data_types: ClassVar[tuple[str, ...]] = ("BOOL", "INT", "REAL", "STRING", "DT")
    can_browse: ClassVar[bool] = True
    serial: ClassVar[str] = "FAKE-1"
    items: ClassVar[list[BrowseItem]] = []
    browse_error: ClassVar[Exception | None] = None

    @classmethod
    def validate_point(cls, point: Point) -> Point:
        """Accept dotted identifiers; the type must be one of ours."""
        if not re.fullmatch(r"[A-Za-z_][\w.]*", point.address):
            raise PlcAddressError(f"{point.address!r} is not a variable name")
        if point.data_type.upper() not in cls.data_types:
            raise PlcAddressError(f"unknown type {point.data_type!r}")
        return Point(point.address, point.data_type.upper())

    async def connect(self) -> DeviceInfo:
        """Report a device with a serial number."""
        return DeviceInfo(vendor=self.vendor, model="Fake PLC", serial=self.serial)

    async def browse(self) -> list[BrowseItem]:
        """Return the class's published variables, or fail."""
        if self.browse_error is not None:
            raise self.browse_error
        return list(self.items)

    async def _read(self, points: Sequence[Point], *, poll: bool) -> ReadResult:
        """Not used by the flow."""
        raise NotImplementedError

    async def _write(self, values: Mapping[Point, Value]) -> dict[Point, PointResult]:
        """Not used by the flow."""
        raise NotImplementedError

    async def read_clock(self) -> datetime:
        """Not used by the flow."""
        raise NotImplementedError

    async def set_clock(self, when: datetime) -> None:
        """Not used by the flow."""
        raise NotImplementedError

    async def close(self) -> None:
        """Nothing to release."""


@pytest.fixture
def fake_vendor(monkeypatch: pytest.MonkeyPatch) -> type[FakeClient]:
    """Register FakeClient as the FAKE_VENDOR module in the real vendor registry.

    The config flow gets the vendor's connection steps too, as a real vendor has them.
    """
    monkeypatch.setitem(vendors._CLIENTS, FAKE_VENDOR, FakeClient)
    for step in ("connection", "reconfigure"):
        monkeypatch.setattr(
            PlcBridgeConfigFlow,
            f"async_step_{step}_{FAKE_VENDOR}",
            PlcBridgeConfigFlow._connection_step,
            raising=False,
        )
    monkeypatch.setattr(FakeClient, "items", [])
    monkeypatch.setattr(FakeClient, "browse_error", None)
    return FakeClient


def strings_at(*path: str) -> Any:
    """Return the strings.json node at a path of keys."""
    node: Any = STRINGS
    for key in path:
        node = node[key]
    return node


def translated(result: Any, *section: str) -> Any:
    """Check that a flow result's step, fields, errors or abort reason are all translated."""
    base = strings_at(*section)
    if result["type"] is FlowResultType.ABORT:
        assert result["reason"] in base["abort"]
        return result
    if result["type"] is FlowResultType.FORM:
        step = base["step"][result["step_id"]]
        assert step["title"]
        schema = result["data_schema"].schema if result["data_schema"] else {}
        for marker, field in schema.items():
            texts = step
            if isinstance(field, form_section):  # its fields' texts are the section's
                texts = step["sections"][str(marker)]
                assert texts["name"], f"section {marker} has no name"
                markers = list(field.schema.schema)
            else:
                markers = [marker]
            for inner in markers:
                assert str(inner) in texts["data"], f"{inner} has no label"
                assert str(inner) in texts["data_description"], f"{inner} has no help text"
    if result["type"] is FlowResultType.MENU:
        step = base["step"][result["step_id"]]
        for option in result["menu_options"]:
            assert option in step["menu_options"], f"{option} has no label"
    if result["type"] is FlowResultType.FORM:
        for key in (result["errors"] or {}).values():
            assert key in base["error"]
    return result


def suggested(result: Any, field: str) -> Any:
    """Return the value a form suggests for a field (None when it suggests none)."""
    for marker in result["data_schema"].schema:
        if str(marker) == field:
            return (marker.description or {}).get("suggested_value")
    raise KeyError(field)


def error_message(result: Any, field: str, *section: str) -> str:
    """Return the English message of a form error, with its placeholders filled in."""
    text: str = strings_at(*section, "error", result["errors"][field])
    return text.format(**(result["description_placeholders"] or {}))


MACHINE = ("config_subentries", SUBENTRY_DEVICE)
"""Where a machine (device subentry) flow's texts are in strings.json."""


async def step(hass: HomeAssistant, result: Any, values: dict[str, Any] | None = None) -> Any:
    """Submit a machine flow's form or menu choice; check its texts."""
    return translated(
        await hass.config_entries.subentries.async_configure(result["flow_id"], values or {}),
        *MACHINE,
    )


async def browse(
    hass: HomeAssistant, entry: MockConfigEntry, needle: str, name: str = "Heating"
) -> Any:
    """Start a machine, open the pick list with a filter; return the pick form."""
    result = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_DEVICE), context={"source": SOURCE_USER}
    )
    menu = await step(hass, result, {"name": name})
    assert "browse" in menu["menu_options"]
    result = await step(hass, menu, {"next_step_id": "browse"})
    return await step(hass, result, {"filter": needle})


def listed(result: Any) -> dict[str, str]:
    """Return the pick list's labels and their values."""
    (selector,) = result["data_schema"].schema.values()
    return {option["label"]: option["value"] for option in selector.config["options"]}


async def polling_form(hass: HomeAssistant, entry: MockConfigEntry) -> Any:
    """Open the PLC's options and choose the poll intervals' page."""
    result = await hass.config_entries.options.async_init(entry.entry_id)
    assert result["type"] is FlowResultType.MENU
    return await hass.config_entries.options.async_configure(
        result["flow_id"], {"next_step_id": "polling"}
    )


async def entity_page(hass: HomeAssistant, menu: Any, platform: str) -> Any:
    """From a machine's menu, open the page of a new entity of several addresses of this kind."""
    kinds = await step(hass, menu, {"next_step_id": "composite"})
    return await step(hass, kinds, {"next_step_id": f"entity_{platform}"})


def on_page(platform: str, values: Mapping[str, Any]) -> dict[str, Any]:
    """Return flat values as the entity's page takes them: each field in its section."""
    kind = KINDS[platform]
    where: dict[str, str] = {"poll": "entity_options", "availability": "entity_options"}
    for name, roles in kind.sections.items():
        for role in roles:
            keys = (role.key, f"{role.key}_data_type", *(f"{role.key}_{s}" for s in role.asks))
            where |= dict.fromkeys(keys, name)
        where |= {setting: name for setting in kind.shared(name) if setting not in where}
    page: dict[str, Any] = {}
    for key, value in values.items():
        if key in where:
            page.setdefault(where[key], {})[key] = value
        else:
            page[key] = value
    return page


def page_shown(result: Any) -> dict[str, Any]:
    """Return the page's suggested values, each section's fields nested in it."""
    values: dict[str, Any] = {}
    for marker, field in result["data_schema"].schema.items():
        if isinstance(field, form_section):
            inner = {
                str(key): key.description["suggested_value"]
                for key in field.schema.schema
                if key.description and "suggested_value" in key.description
            }
            values[str(marker)] = inner
        elif marker.description and "suggested_value" in marker.description:
            values[str(marker)] = marker.description["suggested_value"]
    return values
