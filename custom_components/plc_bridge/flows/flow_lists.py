"""The lists the device flow shows: the PLC's variables to pick, the device's points, problems."""

from __future__ import annotations

from collections import Counter
from collections.abc import Collection, Iterable, Mapping
from dataclasses import dataclass
import re
from typing import Any

from homeassistant.const import CONF_NAME
from homeassistant.core import HomeAssistant
from homeassistant.helpers.selector import (
    SelectOptionDict,
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
)
from homeassistant.helpers.translation import async_get_translations
import voluptuous as vol

from ..const import CONF_ADDRESS, CONF_DATA_TYPE, CONF_PLATFORM, CONF_ROLE, DOMAIN
from ..model.point_table import Describe, point_order
from ..model.points import point_data
from ..plc import BrowseItem, PlcClient, PlcError, Point, ValueKind
from .point_form import browse_values

CONF_FILTER = "filter"
CONF_VARIABLES = "variables"
MAX_LISTED = 50
"""Variables listed at most in one pick list: a real PLC publishes hundreds; filter first."""
MAX_SHOWN = 20
"""Problems shown at most (the rest are counted)."""
MENU_SHOWN = 5
"""Points listed in the menu at most, so that its choices stay in view."""
SEGMENT = re.compile(r"[^./\[\]]+(?:\[[^\]]*\])*")


def listing(lines: list[str], limit: int = MAX_SHOWN) -> str:
    """Return lines as a Markdown list of at most `limit`, and how many more there are."""
    shown = [f"- {line}" for line in lines[:limit]]
    if len(lines) > limit:
        shown.append(f"- … (+{len(lines) - limit})")
    return "\n".join(shown)


def in_order(points: Mapping[str, Mapping[str, Any]]) -> list[tuple[str, Mapping[str, Any]]]:
    """Return a device's points by name (Word 2 before Word 10), then address, every time."""
    return sorted(points.items(), key=lambda pair: point_order(pair[1]))


LISTING = "point_listing"
"""The selector translations naming a point's role in lists (and a bit's data type)."""


@dataclass(frozen=True, slots=True)
class PointWords:
    """How lists name a point's kind, role and data type, in Home Assistant's language."""

    types: Mapping[str, str]
    kinds: Mapping[str, str]
    roles: Mapping[str, str]
    page: Mapping[str, str]
    """The entity page's titles: `new` and `edit`, with `{kind}` and `{name}` to fill."""


async def async_point_words(hass: HomeAssistant) -> PointWords:
    """Return the words lists name points with, in Home Assistant's language."""
    texts = await async_get_translations(hass, hass.config.language, "selector", [DOMAIN])

    def options(key: str) -> dict[str, str]:
        """Return one selector's option labels by option."""
        prefix = f"component.{DOMAIN}.selector.{key}.options."
        return {k.removeprefix(prefix): text for k, text in texts.items() if k.startswith(prefix)}

    kinds = {**options("composite_platform"), **options(CONF_PLATFORM)}
    return PointWords(options(CONF_DATA_TYPE), kinds, options(LISTING), options("entity_page"))


def lowered(label: str) -> str:
    """Return a label as it reads inside a sentence: `Cover` gives cover, `HVAC mode` stays."""
    label = re.sub(r" \(.*\)$", "", label)  # a kind's own explanation, in its list only
    return label[:1].lower() + label[1:] if label[1:2].islower() else label


def point_label(client: type[PlcClient], data: Mapping[str, Any], words: PointWords) -> str:
    """Return how lists name a point: `Shutter (cover) – open command: V60.0 (bit)`."""
    platform, role = str(data[CONF_PLATFORM]), str(data.get(CONF_ROLE) or "")
    kind = lowered(words.kinds.get(platform, platform))
    point = Point(str(data[CONF_ADDRESS]), str(data[CONF_DATA_TYPE]))
    try:
        bit = client.value_kind(client.validate_point(point)) is ValueKind.BOOL
    except PlcError:
        bit = False
    data_type = words.roles.get("bit", "bit") if bit else words.types.get(point.data_type)
    role_words = f" – {words.roles.get(role, role)}" if role else ""
    return (
        f"{data[CONF_NAME]} ({kind}){role_words}: {point.address} ({data_type or point.data_type})"
    )


def menu_listing(
    points: Mapping[str, Mapping[str, Any]], client: type[PlcClient], words: PointWords
) -> str:
    """Return the menu's list of a machine's first points, by name, each named in full."""
    return listing([point_label(client, data, words) for _, data in in_order(points)], MENU_SHOWN)


async def async_type_names(hass: HomeAssistant) -> dict[str, str]:
    """Return the data types' names in Home Assistant's language (an IEC type is its own)."""
    return dict((await async_point_words(hass)).types)


def point_choice(
    points: Mapping[str, Mapping[str, Any]],
    client: type[PlcClient],
    words: PointWords,
    *,
    multiple: bool,
) -> SelectSelector:
    """Return the device's points, each named in full: a dropdown, or boxes to tick."""
    return SelectSelector(
        SelectSelectorConfig(
            options=[
                SelectOptionDict(value=pid, label=point_label(client, data, words))
                for pid, data in in_order(points)
            ],
            multiple=multiple,
            mode=SelectSelectorMode.LIST if multiple else SelectSelectorMode.DROPDOWN,
        )
    )


def titled(item: BrowseItem) -> bool:
    """True when the PLC gives the variable a title of its own, not (the end of) its path."""
    return bool(item.name) and not item.address.endswith(item.name or "")


def variable_label(item: BrowseItem) -> str:
    """Return how a published variable is listed: its title, address and type (`?`: guessed)."""
    name = f"{item.name} – " if titled(item) else ""
    return f"{name}{item.address} ({item.data_type}{'?' if item.guessed else ''})"


def matching(
    items: Iterable[BrowseItem], needle: str, taken: Collection[Point]
) -> list[BrowseItem]:
    """Return the variables that are no point yet whose name or address holds the text.

    Those the PLC gives a title come first, each group in the PLC's order.
    """
    used = {point.address for point in taken}  # under any type: one variable, one point
    found = [item for item in items if item.address not in used and holds(item, needle)]
    return sorted(found, key=lambda item: not titled(item))


def holds(item: BrowseItem, needle: str) -> bool:
    """True when the variable's name or address holds the text (not case sensitive)."""
    needle = needle.strip().lower()
    return needle in item.address.lower() or needle in (item.name or "").lower()


def path_parts(path: str) -> list[str]:
    """Return a variable path's parts after its component; a trailing `value` names its owner."""
    parts = SEGMENT.findall(path.rpartition("/")[2])
    if len(parts) > 1 and parts[-1].lower() == "value":
        parts.pop()
    return parts


def readable(parts: list[str]) -> str:
    """Return a point name from path parts: `plcData`, `varBool0` gives "Plc data var bool 0"."""
    text = " ".join(parts).replace("_", " ")
    words = re.sub(r"(?<=[a-z])(?=[A-Z])|(?<=[A-Za-z])(?=\d)", " ", text).split()
    name = " ".join(w.lower() if i and w[1:].islower() else w for i, w in enumerate(words))
    return name[:1].upper() + name[1:]


def point_names(items: list[BrowseItem]) -> list[str]:
    """Return a name for each picked variable: its title, else its path's last parts, distinct."""
    paths = [[] if titled(item) else path_parts(item.address) for item in items]
    depth = [1] * len(items)
    while True:
        names = [
            readable(parts[-depth[i] :]) if parts else str(items[i].name)
            for i, parts in enumerate(paths)
        ]
        twice = {name for name, count in Counter(names).items() if count > 1}
        grow = [i for i, name in enumerate(names) if name in twice and depth[i] < len(paths[i])]
        if not grow:
            return names
        for i in grow:
            depth[i] += 1


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
    items = list(items)
    for item, name in zip(items, point_names(items), strict=True):
        values = browse_values(client, item) | {CONF_NAME: name}
        data, errors, placeholders = point_data(client, values)
        if errors:
            texts = dict.fromkeys(describe(key, placeholders) for key in errors.values())
            refused.append(f"{item.address}: {' '.join(texts)}")
        else:
            points.append(data)
    return points, refused


def filled(message: str, placeholders: Mapping[str, str]) -> str:
    """Return a message with its placeholders filled in (one not given: empty), as shown."""
    text = re.sub(r"\{(\w+)\}", lambda found: placeholders.get(found[1], ""), message)
    return text.replace("''", "'")
