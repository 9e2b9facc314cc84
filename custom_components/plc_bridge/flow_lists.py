"""The lists the device flow shows: the PLC's variables to pick, the device's points, problems."""

from __future__ import annotations

from collections.abc import Collection, Iterable, Mapping
from typing import Any

from homeassistant.const import CONF_NAME
from homeassistant.helpers.selector import (
    SelectOptionDict,
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
)
import voluptuous as vol

from .const import CONF_ADDRESS
from .plc import BrowseItem, PlcClient, Point
from .point_form import browse_values, point_data
from .point_table import Describe

CONF_FILTER = "filter"
CONF_VARIABLES = "variables"
MAX_LISTED = 200
"""Variables listed at most in one pick list: a real PLC publishes hundreds; filter first."""
MAX_SHOWN = 20
"""Points listed in the menu, and problems shown, at most (the rest are counted)."""


def listing(lines: list[str]) -> str:
    """Return lines as a Markdown list of at most MAX_SHOWN, and how many more there are."""
    shown = [f"- {line}" for line in lines[:MAX_SHOWN]]
    if len(lines) > MAX_SHOWN:
        shown.append(f"- … (+{len(lines) - MAX_SHOWN})")
    return "\n".join(shown)


def point_choice(points: Mapping[str, Mapping[str, Any]], *, multiple: bool) -> SelectSelector:
    """Return a dropdown of the device's points by name and address."""
    return SelectSelector(
        SelectSelectorConfig(
            options=[
                SelectOptionDict(value=pid, label=f"{data[CONF_NAME]} ({data[CONF_ADDRESS]})")
                for pid, data in points.items()
            ],
            multiple=multiple,
            mode=SelectSelectorMode.DROPDOWN,
        )
    )


def variable_label(item: BrowseItem) -> str:
    """Return how a published variable is listed: its name, address and type (`?`: guessed)."""
    name = f"{item.name} – " if item.name and item.name != item.address else ""
    return f"{name}{item.address} ({item.data_type}{'?' if item.guessed else ''})"


def matching(
    items: Iterable[BrowseItem], needle: str, taken: Collection[Point]
) -> list[BrowseItem]:
    """Return the variables that are no point yet whose name or address holds the text."""
    needle = needle.strip().lower()
    used = {point.address for point in taken}  # under any type: one variable, one point
    return [
        item
        for item in items
        if item.address not in used
        and (needle in item.address.lower() or needle in (item.name or "").lower())
    ]


def pick_schema(items: list[BrowseItem]) -> vol.Schema:
    """Return the pick form: the first MAX_LISTED variables, any number to tick."""
    options = [
        SelectOptionDict(value=str(index), label=variable_label(item))
        for index, item in enumerate(items[:MAX_LISTED])
    ]
    return vol.Schema(
        {
            vol.Optional(CONF_VARIABLES): SelectSelector(
                SelectSelectorConfig(options=options, multiple=True, mode=SelectSelectorMode.LIST)
            )
        }
    )


def picked_points(
    client: type[PlcClient], items: Iterable[BrowseItem], describe: Describe
) -> tuple[list[dict[str, Any]], list[str]]:
    """Return the points of the ticked variables, and why any of them cannot be one."""
    points: list[dict[str, Any]] = []
    refused: list[str] = []
    for item in items:
        data, errors, placeholders = point_data(client, browse_values(client, item))
        if errors:
            texts = dict.fromkeys(describe(key, placeholders) for key in errors.values())
            refused.append(f"{item.address}: {' '.join(texts)}")
        else:
            points.append(data)
    return points, refused
