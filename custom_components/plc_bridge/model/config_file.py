"""The whole PLC as a YAML file: an entry written out without its secrets, and read back.

The file carries the entry as it is stored, whatever its keys: the connection (entry data),
the options and every subentry of every type with its data, so that settings added later
travel without code here. Only the secrets are left out, by the list below.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
import json
from typing import Any, NoReturn

from homeassistant.config_entries import ConfigEntry, ConfigSubentry, ConfigSubentryData
from homeassistant.const import CONF_ENTITY_ID, CONF_HOST, CONF_NAME, CONF_PORT
import yaml

from ..const import (
    CONF_ADDRESS,
    CONF_DATA_TYPE,
    CONF_MAC,
    CONF_OPTIONS,
    CONF_POINTS,
    CONF_TLS,
    CONF_VENDOR,
    SUBENTRY_DEVICE,
    SUBENTRY_EXPOSE,
)
from ..plc import PlcClient
from ..plc.vendors import client_class, implemented
from .config_keys import (
    CONNECTION,
    FILE,
    MAPPING,
    OPTIONS,
    POINT,
    SUBENTRY,
    SUBENTRY_DATA,
    Keys,
    kind_error,
    vendor_option_keys,
)
from .plc_config import PlcConfig
from .point_table import Describe, plain, point_order
from .template import (
    CONF_COPY_OF,
    CONF_NUMBER,
    CONF_TEMPLATE,
    CONF_TEMPLATE_ID,
    COPY_KEYS,
    TEMPLATE_KEYS,
    Template,
    TemplateError,
    make_copies,
    record_error,
    record_problem,
)
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

    def plc(self) -> PlcConfig:
        """Return the PLC the file holds, typed as a stored one."""
        return PlcConfig.from_stored(
            title=self.title,
            version=self.version,
            minor_version=self.minor_version,
            data=self.data,
            options=self.options,
            subentries=self.subentries,
        )


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
    subentries = [
        ConfigSubentryData(
            data=subentry.get("data", {}),
            subentry_type=subentry["type"],
            title=subentry["title"],
            unique_id=subentry.get("unique_id"),
        )
        for subentry in document.get("subentries", [])
    ]
    return ConfigFile(
        title=document["title"],
        version=document["version"],
        minor_version=document.get("minor_version", 1),
        data={CONF_OPTIONS: {}, **data},
        secrets=tuple(dict.fromkeys(secrets)),
        options=document.get("options", {}),
        subentries=subentries + _missing_copies(read, client_class(data[CONF_VENDOR]), subentries),
        source=read,
    )


def _missing_copies(
    read: YamlText, client: type[PlcClient], subentries: list[ConfigSubentryData]
) -> list[ConfigSubentryData]:
    """Return the copies a machine's template names that the file does not hold, made anew.

    A copy the file holds is taken as written (it may have been edited since it was made);
    each template record and copy mark is checked, and the copies made are checked as the
    form checks them (model/template.py), on the line of their template.
    """
    machines = {
        index: subentry
        for index, subentry in enumerate(subentries)
        if subentry["subentry_type"] == SUBENTRY_DEVICE
    }
    templates: dict[str, int] = {}
    present: dict[str, set[int]] = {}
    for index, subentry in machines.items():
        path = ("subentries", index, "data")
        if CONF_TEMPLATE in subentry["data"]:
            record = subentry["data"][CONF_TEMPLATE]
            if (key := record_error(record, TEMPLATE_KEYS)) is not None:
                _refuse(read, (*path, CONF_TEMPLATE), "config_bad_value", key, CONF_TEMPLATE)
            templates[str(record[CONF_TEMPLATE_ID])] = index
        if CONF_COPY_OF in subentry["data"]:
            mark = subentry["data"][CONF_COPY_OF]
            if (key := record_error(mark, COPY_KEYS)) is not None:
                _refuse(read, (*path, CONF_COPY_OF), "config_bad_value", key, CONF_COPY_OF)
            present.setdefault(str(mark[CONF_TEMPLATE_ID]), set()).add(int(mark[CONF_NUMBER]))
    for template_id in present.keys() - templates.keys():
        index = next(
            i
            for i, subentry in machines.items()
            if str(subentry["data"].get(CONF_COPY_OF, {}).get(CONF_TEMPLATE_ID)) == template_id
        )
        raise ConfigFileError(
            "config_template",
            line=str(read.line(("subentries", index, "data", CONF_COPY_OF))),
            name=machines[index]["title"],
            problem=f"no machine of the file holds the template {template_id}",
        )
    made: list[ConfigSubentryData] = []
    for template_id, index in templates.items():
        original = machines[index]
        template = Template.from_data(original["data"][CONF_TEMPLATE])
        if (problem := record_problem(client, template)) is not None:
            raise ConfigFileError(
                "config_template",
                line=str(read.line(("subentries", index, "data", CONF_TEMPLATE))),
                name=original["title"],
                problem=problem,
            )
        missing = [
            number
            for number in range(2, template.count + 2)
            if number not in present.get(template_id, set())
        ]
        plc = [(machine["title"], machine["data"]) for machine in machines.values()]
        plc += [(copy["title"], copy["data"]) for copy in made]
        try:
            copies = make_copies(client, template, original["data"], 0, plc, numbers=missing)
        except TemplateError as err:
            raise ConfigFileError(
                "config_template",
                line=str(read.line(("subentries", index, "data", CONF_TEMPLATE))),
                name=original["title"],
                problem=str(err),
            ) from err
        made += [
            ConfigSubentryData(
                data=copy.data, subentry_type=SUBENTRY_DEVICE, title=copy.title, unique_id=None
            )
            for copy in copies
        ]
    return made


def _check_connection(read: YamlText, data: Mapping[str, Any]) -> None:
    """Raise ConfigFileError for a vendor option the connection pages never store."""
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


def check_pasted(
    client: type[PlcClient], pasted: ConfigFile, describe: Describe = plain
) -> list[ConfigSubentryData]:
    """Raise ConfigFileError for the first thing no form would store, on its line.

    The one validation of a stored PLC (`PlcConfig.problems`) decides; the subentries are
    returned with each expose as its form stores it, sending off.
    """
    plc = pasted.plc()
    for problem in plc.problems(client, describe)[:1]:
        line = pasted.line(problem.path)
        raise ConfigFileError(problem.key, line=line, **problem.placeholders)
    return plc.sending_off(client)
