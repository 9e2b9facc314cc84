"""The whole PLC as a YAML file: an entry written out without its secrets, and read back.

The file carries the entry as it is stored, whatever its keys: the connection (entry data),
the options and every subentry of every type with its data, so that settings added later
travel without code here. Only the secrets are left out, by the list below.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass
import json
from typing import Any, NoReturn

from homeassistant.config_entries import ConfigEntry, ConfigSubentry, ConfigSubentryData
from homeassistant.const import CONF_ENTITY_ID, CONF_HOST, CONF_NAME, CONF_PORT, CONF_SCAN_INTERVAL
import yaml

from ..const import (
    CONF_ADDRESS,
    CONF_DATA_TYPE,
    CONF_MAC,
    CONF_OPTIONS,
    CONF_PLATFORM,
    CONF_POINTS,
    CONF_READ_ONLY,
    CONF_ROLE,
    CONF_TLS,
    CONF_VENDOR,
    SUBENTRY_DEVICE,
    SUBENTRY_EXPOSE,
)
from ..plc import PlcClient, PlcError, Point, TlsMode
from ..plc.vendors import implemented
from .availability import (
    CONF_AVAILABILITY_ADDRESS,
    CONF_AVAILABILITY_DATA_TYPE,
    check_policy,
    has_data_valid,
    policy_differs,
)
from .composite import as_platform, is_part, point_classes, supervision_data, travel_data
from .config_keys import (
    CONNECTION,
    FILE,
    MAPPING,
    OPTIONS,
    POINT,
    SUBENTRY,
    SUBENTRY_DATA,
    TEXT,
    Keys,
    kind_error,
    vendor_option_keys,
)
from .expose import CONF_SEND, check_expose
from .point_table import point_order
from .points import PointConfig, read_only_errors
from .poll_classes import (
    CONF_FAST_INTERVAL,
    FAST,
    INTERVALS,
    NORMAL,
    SECONDS_MAX,
    SECONDS_MIN,
    class_minimums,
    interval_errors,
    unset,
)
from .write_rules import layout_conflicts
from .yaml_text import Path, YamlText, YamlTextError, read_yaml

FORMAT_KEY = "plc_bridge"
FORMAT = 1
"""The version of the file's own layout (not the entry's: that is `version`)."""

SECRETS = ("password", "token", "cookie", "client_certificate", "client_key")
"""Keys never written, in the entry data or its vendor options: the import asks for them.

A SoftPLC's client certificate goes with its key; together they let anyone write to the PLC.
"""

HEADER = (
    "# A PLC of PLC Bridge. Add it with Add integration > PLC Bridge > Paste a configuration\n"
    "# exported from PLC Bridge; the secrets listed under `secrets` are asked for then.\n"
)

ADDRESS_KEYS = (
    (CONF_ADDRESS, CONF_DATA_TYPE),
    (CONF_AVAILABILITY_ADDRESS, CONF_AVAILABILITY_DATA_TYPE),
)
"""The keys of an address and its data type, wherever they stand in a subentry's data."""


class ConfigFileError(Exception):
    """A pasted text that cannot become a PLC: a config flow error key and its placeholders."""

    def __init__(self, key: str, **placeholders: str) -> None:
        """Keep the error key and what its message names."""
        super().__init__(key, placeholders)
        self.key = key
        self.placeholders = placeholders


@dataclass(frozen=True, slots=True)
class ConfigFile:
    """A PLC read from a file: its entry as stored, less the secrets the file left out."""

    title: str
    version: int
    minor_version: int
    data: dict[str, Any]
    secrets: tuple[str, ...]
    options: dict[str, Any]
    subentries: list[ConfigSubentryData]
    source: YamlText | None = None  # the text it was read from: the line of each key

    def line(self, path: Path) -> str:
        """Return the line of a path of the file, as text ("?" for a file not read from text)."""
        return str(self.source.line(path)) if self.source is not None else "?"

    @property
    def vendor(self) -> str:
        """The vendor key of the PLC."""
        return str(self.data[CONF_VENDOR])


def dump_config(entry: ConfigEntry[Any]) -> str:
    """Return an entry as a YAML file, secrets left out, ordered to diff well in git."""
    data = {
        key: value
        for key, value in entry.data.items()
        if not _secret(key, value) and key != CONF_MAC  # a discovery's, of this installation
    }
    options = dict(entry.data.get(CONF_OPTIONS) or {})
    data[CONF_OPTIONS] = {key: value for key, value in options.items() if not _secret(key, value)}
    removed = [key for key in SECRETS if entry.data.get(key) or options.get(key)]
    subentries = sorted(entry.subentries.values(), key=_subentry_order)
    document = {
        FORMAT_KEY: FORMAT,
        "version": entry.version,
        "minor_version": entry.minor_version,
        "title": entry.title,
        "connection": _plain(data),
        "secrets": removed,
        "options": _plain(entry.options),
        "subentries": [
            {
                "type": subentry.subentry_type,
                "title": subentry.title,
                "unique_id": subentry.unique_id,
                "data": _subentry_data(subentry.data),
            }
            for subentry in subentries
        ],
    }
    text: str = yaml.safe_dump(
        document, sort_keys=False, allow_unicode=True, default_flow_style=False, width=100
    )
    return HEADER + text


def _secret(key: str, value: Any) -> bool:
    """True for a secret that is set (an empty password, of a PLC without users, is kept)."""
    return key in SECRETS and bool(value)


def _subentry_order(subentry: ConfigSubentry) -> tuple[str, str, str, str]:
    """Return the key that orders subentries: by type, title, unique id, then content."""
    return (
        subentry.subentry_type,
        subentry.title.casefold(),
        subentry.unique_id or "",
        json.dumps(_plain(subentry.data), default=str),
    )


def _subentry_data(data: Mapping[str, Any]) -> dict[str, Any]:
    """Return a subentry's data with sorted keys, its points ordered as `export_points` lists."""
    plain: dict[str, Any] = _plain(data)
    points = plain.get(CONF_POINTS)
    if isinstance(points, dict) and all(
        isinstance(point, dict) and CONF_NAME in point and CONF_ADDRESS in point
        for point in points.values()
    ):
        ordered = sorted(points.items(), key=lambda item: (point_order(item[1]), item[0]))
        plain[CONF_POINTS] = dict(ordered)
    return plain


def _plain(value: Any) -> Any:
    """Return stored data as plain YAML values: mappings with sorted keys, lists for sequences."""
    if isinstance(value, Mapping):
        return {str(key): _plain(value[key]) for key in sorted(value, key=str)}
    if isinstance(value, list | tuple):
        return [_plain(item) for item in value]
    return value


def load_config(text: str, version: int) -> ConfigFile:
    """Return the PLC a pasted file describes; raise ConfigFileError on what cannot be used.

    Blocking (an executor's work): the text is read as plain YAML data only, every key checked
    against the keys its level may hold and every value against its key's kind, on its line.
    `version` is the newest entry version this release knows: a file of a newer one is
    refused, an older one is created at its own version and migrated as stored entries are.
    """
    try:
        read = read_yaml(text)
    except YamlTextError as err:
        raise ConfigFileError(err.key, **err.placeholders) from err
    document = read.data
    if not isinstance(document, dict) or FORMAT_KEY not in document:
        raise ConfigFileError("config_not_ours")
    _check_level(read, (), FILE, ("plc_bridge", "version", "title", "connection"))
    if document[FORMAT_KEY] > FORMAT or document["version"] > version:
        raise ConfigFileError("config_newer")
    _check_level(read, ("connection",), CONNECTION, (CONF_VENDOR, CONF_HOST, CONF_PORT, CONF_TLS))
    data: dict[str, Any] = document["connection"]
    if data[CONF_VENDOR] not in implemented():
        raise ConfigFileError("config_unknown_vendor", vendor=data[CONF_VENDOR])
    _check_connection(read, data)
    if "options" in document:
        _check_level(read, ("options",), OPTIONS, ())
    secrets = document.get("secrets", [])
    for index, secret in enumerate(secrets):
        if secret not in SECRETS:
            _refuse(read, ("secrets", index), "config_bad_value", str(secret), "secret")
    for index, _ in enumerate(document.get("subentries", [])):
        _check_subentry(read, ("subentries", index))
    return ConfigFile(
        title=document["title"],
        version=document["version"],
        minor_version=document.get("minor_version", 1),
        data={CONF_OPTIONS: {}, **data},
        secrets=tuple(dict.fromkeys(secrets)),
        options=document.get("options", {}),
        subentries=[
            ConfigSubentryData(
                data=subentry.get("data", {}),
                subentry_type=subentry["type"],
                title=subentry["title"],
                unique_id=subentry.get("unique_id"),
            )
            for subentry in document.get("subentries", [])
        ],
        source=read,
    )


def _check_connection(read: YamlText, data: Mapping[str, Any]) -> None:
    """Raise ConfigFileError for a connection value the connection page would not take."""
    if not data[CONF_HOST].strip():
        _refuse(read, ("connection", CONF_HOST), "config_bad_value", CONF_HOST, TEXT)
    if not 1 <= data[CONF_PORT] <= 65535:
        _refuse(read, ("connection", CONF_PORT), "config_bad_value", CONF_PORT, "1 to 65535")
    if data[CONF_TLS] not in [mode.value for mode in TlsMode]:
        modes = ", ".join(mode.value for mode in TlsMode)
        _refuse(read, ("connection", CONF_TLS), "config_bad_value", CONF_TLS, modes)
    if CONF_OPTIONS in data:
        keys = vendor_option_keys(data[CONF_VENDOR])
        _check_level(read, ("connection", CONF_OPTIONS), keys, ())


def _check_subentry(read: YamlText, path: Path) -> None:
    """Raise ConfigFileError for a subentry's key or value the forms never store, on its line."""
    _check_level(read, path, SUBENTRY, ("type", "title"))
    subentry = _at(read, path)
    kind = subentry["type"]
    if kind not in SUBENTRY_DATA:
        _refuse(read, (*path, "type"), "config_bad_value", "type", ", ".join(SUBENTRY_DATA))
    if "data" not in subentry:
        return
    required = (CONF_ENTITY_ID, CONF_ADDRESS, CONF_DATA_TYPE) if kind == SUBENTRY_EXPOSE else ()
    _check_level(read, (*path, "data"), SUBENTRY_DATA[kind], required)
    if kind == SUBENTRY_DEVICE:
        for point_id in subentry["data"].get(CONF_POINTS, {}):
            point = (*path, "data", CONF_POINTS, point_id)
            _check_level(read, point, POINT, (CONF_NAME, CONF_ADDRESS, CONF_DATA_TYPE))


def _at(read: YamlText, path: Path) -> Any:
    """Return the value at a path of the document."""
    value = read.data
    for step in path:
        value = value[step]
    return value


def _check_level(read: YamlText, path: Path, keys: Keys, required: tuple[str, ...]) -> None:
    """Raise ConfigFileError for an unknown key, a missing one or a value of the wrong kind."""
    level = _at(read, path)
    if not isinstance(level, dict):
        _refuse(read, path, "config_bad_value", str(path[-1]) if path else "", MAPPING)
    for key, value in level.items():
        if key not in keys:
            _refuse(read, (*path, key), "config_unknown_key", key, "")
        if kind_error(keys[key], value):
            _refuse(read, (*path, key), "config_bad_value", key, keys[key])
    for key in required:
        if key not in level:
            _refuse(read, path, "config_missing_key", key, "")


def _refuse(read: YamlText, path: Path, key: str, name: str, kind: str) -> NoReturn:
    """Raise the error of a key, on the line it stands on."""
    raise ConfigFileError(key, line=str(read.line(path)), name=name, kind=kind)


def check_addresses(client: type[PlcClient], pasted: ConfigFile) -> None:
    """Raise ConfigFileError for the first point whose address the vendor's parser refuses.

    A point is any mapping of a subentry's data with an address and a data type: the points of
    a device, the parts of an entity of several points, and whatever else names an address.
    """
    for subentry in pasted.subentries:
        for name, point in _addressed(subentry["data"], subentry["title"]):
            try:
                client.validate_point(point)
            except PlcError as err:
                raise ConfigFileError(
                    "config_bad_address",
                    point=name,
                    address=point.address,
                    problem=str(err),
                ) from err
    check_points(client, pasted)


def check_points(client: type[PlcClient], pasted: ConfigFile) -> None:
    """Raise ConfigFileError for the first point the forms would refuse as it is laid out.

    A command stored read only, a travel or supervision time out of bounds or on an entity
    without travel or supervision, an unknown availability policy or one following a data-valid
    address its machine does not name, and a write that would meet read-only data (another
    point's, or data its vendor writes with it) are refused as the forms and tables refuse them.
    """
    points = [
        data
        for subentry in pasted.subentries
        for data in (subentry["data"].get(CONF_POINTS) or {}).values()
        if isinstance(data, Mapping) and CONF_ADDRESS in data and CONF_DATA_TYPE in data
    ]
    for subentry in pasted.subentries:
        data_valid = has_data_valid(subentry["data"])
        for data in (subentry["data"].get(CONF_POINTS) or {}).values():
            if isinstance(data, Mapping) and check_policy(data, data_valid=data_valid)[1]:
                raise ConfigFileError("config_availability_policy", point=_named(data))
        rows = (subentry["data"].get(CONF_POINTS) or {}).values()
        for name in policy_differs(data for data in rows if isinstance(data, Mapping))[:1]:
            raise ConfigFileError("config_availability_policy", point=name)
    for data in points:
        platform, role = str(data.get(CONF_PLATFORM, "")), str(data.get(CONF_ROLE) or "")
        read_only = bool(data.get(CONF_READ_ONLY))
        if read_only_errors(as_platform(platform, role), role, read_only):
            raise ConfigFileError(
                "config_command_read_only", point=_named(data), address=str(data[CONF_ADDRESS])
            )
        if travel_data(platform, data)[1]:
            raise ConfigFileError("config_travel_time", point=_named(data))
        if supervision_data(platform if is_part(platform, role) else "", data)[1]:
            raise ConfigFileError("config_supervision", point=_named(data))
    for data, conflict in layout_conflicts(client, [], points)[:1]:
        other = conflict.other.address if conflict.other else ""
        key = "config_writes_read_only" if conflict.key == "writes_read_only" else "config_overlap"
        raise ConfigFileError(key, point=_named(data), address=conflict.point.address, other=other)


def _named(data: Mapping[str, Any]) -> str:
    """Return a point's name for a message: its entity's name and, for a part, its role."""
    role = data.get(CONF_ROLE)
    return f"{data.get(CONF_NAME, '')} ({role})" if role else str(data.get(CONF_NAME, ""))


def _addressed(value: Any, name: str) -> Iterator[tuple[str, Point]]:
    """Yield every point a value names, with the name of what it belongs to.

    A point is an address and a data type, or a machine's availability address and its type.
    """
    if isinstance(value, Mapping):
        for address, data_type in ADDRESS_KEYS:
            if address in value and data_type in value:
                point = Point(str(value[address]), str(value[data_type]))
                yield str(value.get(CONF_NAME) or name), point
        for key, item in value.items():
            yield from _addressed(item, f"{name} {key}" if key != CONF_POINTS else name)
    elif isinstance(value, list):
        for item in value:
            yield from _addressed(item, name)


def check_intervals(client: type[PlcClient], pasted: ConfigFile) -> None:
    """Raise ConfigFileError for a poll interval the options form would refuse, on its line."""
    configs = {
        point_id: PointConfig(point_id, str(index), data)
        for index, subentry in enumerate(pasted.subentries)
        if subentry["subentry_type"] == SUBENTRY_DEVICE
        for point_id, data in (subentry["data"].get(CONF_POINTS) or {}).items()
    }
    every_poll = [
        Point(str(data[CONF_AVAILABILITY_ADDRESS]), str(data[CONF_AVAILABILITY_DATA_TYPE]))
        for subentry in pasted.subentries
        if (data := subentry["data"]).get(CONF_AVAILABILITY_ADDRESS)
        and CONF_AVAILABILITY_DATA_TYPE in data
    ]
    points = list(dict.fromkeys(config.point for config in configs.values()))
    polled = list(dict.fromkeys([*every_poll, *points]))
    minimums = class_minimums(client, point_classes(configs, every_poll), polled)
    given = {key: float(value) for key, value in pasted.options.items() if key in INTERVALS}
    for key, value in given.items():
        if not SECONDS_MIN <= value <= SECONDS_MAX:  # the form's own field bounds
            line = pasted.line(("options", key))
            raise ConfigFileError(
                "config_interval", line=line, name=key, minimum=f"{SECONDS_MIN:g}"
            )
    for key in interval_errors(unset(client, given, minimums), minimums):
        line = pasted.line(("options", key if key in given else CONF_SCAN_INTERVAL))
        least = minimums[FAST if key == CONF_FAST_INTERVAL else NORMAL]
        raise ConfigFileError("config_interval", line=line, name=key, minimum=f"{least:g}")


def check_exposes(client: type[PlcClient], pasted: ConfigFile) -> list[ConfigSubentryData]:
    """Return the subentries with each expose as its form stores it, sending off.

    Each expose passes the one validation of an expose (`check_expose`); the first refused
    raises ConfigFileError on the line of its field. Its feedback is checked when the user
    turns sending on: the entities it would follow do not exist yet.
    """
    read_only = [
        Point(str(data[CONF_ADDRESS]), str(data[CONF_DATA_TYPE]))
        for subentry in pasted.subentries
        for data in (subentry["data"].get(CONF_POINTS) or {}).values()
        if isinstance(data, Mapping) and data.get(CONF_READ_ONLY)
    ]
    exposes = {
        index: Point(str(subentry["data"][CONF_ADDRESS]), str(subentry["data"][CONF_DATA_TYPE]))
        for index, subentry in enumerate(pasted.subentries)
        if subentry["subentry_type"] == SUBENTRY_EXPOSE
    }
    subentries: list[ConfigSubentryData] = []
    for index, subentry in enumerate(pasted.subentries):
        if index not in exposes:
            subentries.append(subentry)
            continue
        taken = [point for other, point in exposes.items() if other < index]
        data, errors, words = check_expose(
            client, subentry["data"], read_only=read_only, taken=taken
        )
        for field, key in errors.items():
            raise ConfigFileError(
                f"config_expose_{key}",
                line=pasted.line(("subentries", index, "data", field)),
                point=subentry["title"],
                **words,
            )
        subentries.append(
            ConfigSubentryData(
                data=data | {CONF_SEND: False},
                subentry_type=SUBENTRY_EXPOSE,
                title=subentry["title"],
                unique_id=subentry["unique_id"],
            )
        )
    return subentries
