"""Points as text: pasted tables imported line by line (export_points writes the format).

The format is CSV with a header row (comma, semicolon or tab separated, as engineering tools
and spreadsheets copy tables). A TIA Portal tag table or a STEP 7-Micro/WIN SMART symbol table
is told by its headers. Every line is checked by the same `point_data` as the forms.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Callable, Collection, Iterable, Mapping
import csv
import io
import re
from typing import Any

from homeassistant.components.sensor import CONF_STATE_CLASS
from homeassistant.const import CONF_DEVICE_CLASS, CONF_NAME, CONF_UNIT_OF_MEASUREMENT
from homeassistant.core import HomeAssistant
from homeassistant.helpers.translation import async_get_translations

from ..const import (
    CONF_ADDRESS,
    CONF_AS_TEXT,
    CONF_DATA_TYPE,
    CONF_INVERT,
    CONF_MAX,
    CONF_MIN,
    CONF_OFFSET,
    CONF_PLATFORM,
    CONF_READ_ONLY,
    CONF_ROLE,
    CONF_SCALE,
    CONF_STEP,
    DOMAIN,
    SUBENTRY_DEVICE,
)
from ..plc import PlcAddressError, PlcClient, Point, ValueKind
from .availability import CONF_AVAILABILITY_POLICY, check_policy, policy_differs
from .composite import (
    as_platform,
    group_errors,
    is_part,
    part_data,
    takes_roles,
)
from .kinds import CONF_SUPERVISION, CONF_TRAVEL_TIME, CONTROLS
from .point_kinds import KIND_COLUMNS, NUMBER_FIELDS, PAIRS_FIELDS
from .points import point_data, point_key, suggested_platform
from .poll_classes import CONF_POLL
from .write_rules import layout_conflicts

COLUMNS = (
    CONF_NAME,
    CONF_ADDRESS,
    CONF_DATA_TYPE,
    CONF_PLATFORM,
    "unit",
    CONF_DEVICE_CLASS,
    CONF_STATE_CLASS,
    CONF_SCALE,
    CONF_OFFSET,
    CONF_MIN,
    CONF_MAX,
    CONF_STEP,
    CONF_READ_ONLY,
    *KIND_COLUMNS,
    CONF_ROLE,
    CONF_POLL,
    CONF_AVAILABILITY_POLICY,
    CONF_AS_TEXT,
    CONF_SUPERVISION,
    CONF_TRAVEL_TIME,
)
"""The columns of the format, in the order export writes them (rows of one entity of several
addresses share its name and platform, and each names its role); an empty poll is normal, an
empty availability the machine's default (availability.py), `as_text` shows a duration as
hh:mm:ss.zzz, and a cover's or valve's rows carry its travel time in seconds (empty: none), a
supervised entity's its supervision time."""
COMMENT = "comment"
HEADERS: dict[str, str] = {
    **{column: column for column in COLUMNS},
    "unit_of_measurement": "unit",
    "type": CONF_DATA_TYPE,
    "datatype": CONF_DATA_TYPE,
    "entity_type": CONF_PLATFORM,
    "readonly": CONF_READ_ONLY,
    COMMENT: COMMENT,
    # TIA Portal tag tables: Name, Path, Data Type, Logical Address, Comment (English, German).
    "logical_address": CONF_ADDRESS,
    "logische_adresse": CONF_ADDRESS,
    "datentyp": CONF_DATA_TYPE,
    "kommentar": COMMENT,
    # STEP 7-Micro/WIN SMART symbol tables: Symbol, Address, Comment.
    "symbol": CONF_NAME,
    "adresse": CONF_ADDRESS,
}
"""Header names (lower case, spaces as underscores) and the column each one means."""
WRITABLE = "writable"
WRITABLE_HEADER = re.compile(
    r"(hmi_)?writ[e]?able(_from_hmi.*)?|(hmi_)?schreibbar(_aus_hmi.*)?|von_hmi.*_schreibbar"
)
"""An engineering tool's "may be written" column: TIA Portal's Hmi Writeable (in the export),
Writable from HMI/OPC UA/Web API (in the editor), Schreibbar aus HMI/OPC UA/Web API."""
SET_FLAGS = (CONF_INVERT, CONF_AS_TEXT)
"""Yes/no columns stored only when yes (an empty cell is no)."""
NUMBERS = (
    *(CONF_SCALE, CONF_OFFSET, CONF_MIN, CONF_MAX, CONF_STEP, *NUMBER_FIELDS),
    *(CONF_TRAVEL_TIME, CONF_SUPERVISION),
)
TRUE = {"1", "true", "yes", "y", "on", "x"}
FALSE = {"", "0", "false", "no", "n", "off"}
SIGNED = ("signed", "INT", "DINT")
"""Types tried when a table names none and the vendor's first type does not fit the address."""
FORMULA = ("=", "+", "-", "@", "\t", "\r", "'")
"""Text cells starting so are exported behind a `'`, lest a spreadsheet run them as formulas."""

type Describe = Callable[[str, Mapping[str, str]], str]
"""Turns a problem's key and placeholders into the text shown for its line."""


def plain(key: str, placeholders: Mapping[str, str]) -> str:
    """Describe a problem without translations: its key and what it names."""
    details = ", ".join(value for value in placeholders.values() if value)
    return f"{key} ({details})" if details else key


async def async_describe(hass: HomeAssistant) -> Describe:
    """Return how problems are worded: as the device flow's errors, in Home Assistant's language."""
    texts = await async_get_translations(hass, hass.config.language, "config_subentries", [DOMAIN])
    prefix = f"component.{DOMAIN}.config_subentries.{SUBENTRY_DEVICE}.error."

    def describe(key: str, placeholders: Mapping[str, str]) -> str:
        """Return the problem's text with its placeholders filled in."""
        return texts.get(prefix + key, key).format_map(defaultdict(str, placeholders))

    return describe


def _header(text: str) -> str:
    """Return a header cell as a key of HEADERS."""
    return re.sub(r"[\s-]+", "_", text.strip().lower())


def _column(text: str) -> str | None:
    """Return the column a header cell names, or None for one the import does not use."""
    key = _header(text)
    return WRITABLE if WRITABLE_HEADER.fullmatch(key) else HEADERS.get(key)


def _rows(text: str) -> tuple[list[str], list[tuple[int, list[str]]]]:
    """Split pasted text into its header and its rows by line number (blank lines dropped)."""
    text = text.lstrip("\ufeff")
    first = next((line for line in text.splitlines() if line.strip()), "")
    reader = csv.reader(io.StringIO(text), delimiter=max(("\t", ";", ","), key=first.count))
    header: list[str] = []
    rows: list[tuple[int, list[str]]] = []
    line = 1
    for row in reader:
        blank = not any(cell.strip() for cell in row)
        if header and not blank:
            rows.append((line, row))
        elif not blank:
            header = row
        line = reader.line_num + 1
    return header, rows


def _flag(text: str) -> bool | None:
    """Return a yes/no cell as a bool, or None when it is neither."""
    word = text.strip().lower()
    return True if word in TRUE else False if word in FALSE else None


def _fits(client: type[PlcClient], address: str, data_type: str) -> bool:
    """True when the vendor's parser takes the address with the type."""
    try:
        client.validate_point(Point(address, data_type))
    except PlcAddressError:
        return False
    return True


def _data_type(client: type[PlcClient], address: str, cells: Mapping[str, str]) -> tuple[str, bool]:
    """Return the cell's type, else the first that fits the address, and whether it was assumed.

    Never from free text: a comment saying "raw analog input" is no type. A type counts as
    assumed where the address takes others that would show a different value.
    """
    if data_type := cells.get(CONF_DATA_TYPE, "").strip():
        return data_type, False
    first = client.data_types[0]
    tried = (first, *(name for name in SIGNED if name in client.data_types), *client.data_types)
    fitting = [name for name in dict.fromkeys(tried) if _fits(client, address, name)]
    if not fitting:
        return first, False
    kinds = {client.value_kind(Point(address, name)) for name in fitting}
    return fitting[0], len(fitting) > 1 and not kinds <= {ValueKind.BOOL, ValueKind.DATETIME}


def first_type(client: type[PlcClient], address: str) -> str:
    """Return the data type a table without a type column gives an address."""
    return _data_type(client, address, {})[0]


def _values(
    client: type[PlcClient], cells: Mapping[str, str]
) -> tuple[dict[str, Any], str, dict[str, str]]:
    """Return a row as the values point_data takes, or the problem with a cell it cannot read.

    A row gets a writable control only where its platform asks for one; without a platform
    it is a sensor or binary sensor, read only unless its read_only cell says no. A "not
    writable" flag of an engineering tool makes it read only.
    """
    address = cells.get(CONF_ADDRESS, "").strip().lstrip("%")
    data_type, _ = _data_type(client, address, cells)
    values: dict[str, Any] = {
        CONF_NAME: cells.get(CONF_NAME, "").strip(),
        CONF_ADDRESS: address,
        CONF_DATA_TYPE: data_type,
    }
    for key in NUMBERS:
        if text := cells.get(key, "").strip():
            try:
                values[key] = float(text.replace(",", "."))  # a decimal comma too
            except ValueError:
                return {}, "import_not_a_number", {"column": key, "text": text}
    flags: dict[str, bool | None] = {}
    for column in (CONF_READ_ONLY, WRITABLE, *SET_FLAGS):
        if text := cells.get(column, "").strip():
            flags[column] = _flag(text)
            if flags[column] is None:
                return {}, "import_not_yes_or_no", {"column": column, "text": text}
    platform = cells.get(CONF_PLATFORM, "").strip().lower().replace(" ", "_")
    if takes_roles(platform):
        values[CONF_ROLE] = cells.get(CONF_ROLE, "").strip().lower().replace(" ", "_")
    read_only = flags.get(CONF_READ_ONLY)
    if read_only is None:
        read_only = as_platform(platform, values.get(CONF_ROLE)) not in CONTROLS
    read_only = read_only or flags.get(WRITABLE) is False
    values[CONF_READ_ONLY] = read_only
    for key in SET_FLAGS:
        values[key] = bool(flags.get(key))
    for key in (*PAIRS_FIELDS, CONF_POLL):
        if cells.get(key, "").strip():
            values[key] = cells[key].strip()
    if policy := cells.get(CONF_AVAILABILITY_POLICY, "").strip().lower():
        values[CONF_AVAILABILITY_POLICY] = policy
    for key, column in (
        (CONF_UNIT_OF_MEASUREMENT, "unit"),
        (CONF_DEVICE_CLASS, CONF_DEVICE_CLASS),
        (CONF_STATE_CLASS, CONF_STATE_CLASS),
    ):
        if cells.get(column, "").strip():
            values[key] = cells[column].strip()
    values[CONF_PLATFORM] = platform or suggested_platform(
        client, address, data_type, read_only=True
    )
    return values, "", {}


def parse_points(
    client: type[PlcClient],
    text: str,
    taken: Collection[Point] = (),
    describe: Describe = plain,
    *,
    assumed: list[tuple[int, str]] | None = None,
    known: Iterable[Mapping[str, Any]] = (),
    plc: Iterable[Mapping[str, Any]] = (),
    data_valid: bool = False,
) -> tuple[list[dict[str, Any]], list[tuple[int, str]]]:
    """Return the points of a pasted table and the errors by line; no points unless no errors.

    `taken` holds the points already configured: a line naming one again is an error, as is a
    line repeating an earlier line's address and data type. `describe` words each problem.
    `assumed` receives, by line, the data types taken where the table names none. `known`:
    the machine's points already, which new parts of an entity of several points join.
    `plc`: the PLC's points already (stored data), whose read-only data no new point's write
    may meet, nor a new read-only point the writes of theirs. `data_valid`: the machine names
    a data-valid address (its points may follow it).
    """
    header, rows = _rows(text)
    columns = [_column(cell) for cell in header]
    if CONF_NAME not in columns or CONF_ADDRESS not in columns:
        return [], [(1, describe("import_no_header", {}))]
    if not rows:
        return [], [(1, describe("import_no_points", {}))]
    points: list[dict[str, Any]] = []
    errors: list[tuple[int, str]] = []
    seen: dict[Point, int] = dict.fromkeys(taken, 0)
    firsts: dict[str, int] = {}  # the line of each entity of several addresses, by its name
    lines: dict[int, int] = {}  # the line of each point, by the id of its data
    for line, row in rows:
        cells = {
            column: _unescaped(cell)
            for column, cell in zip(columns, row, strict=False)
            if column is not None
        }
        values, problem, placeholders = _values(client, cells)
        if problem:
            errors.append((line, describe(problem, placeholders)))
            continue
        part = is_part(values[CONF_PLATFORM], values.get(CONF_ROLE))
        data, found, placeholders = (part_data if part else point_data)(client, values)
        if not part and values.get(CONF_TRAVEL_TIME):
            found[CONF_TRAVEL_TIME] = "travel_time_not_here"
        if not part and values.get(CONF_SUPERVISION):
            found[CONF_SUPERVISION] = "supervision_not_here"
        policy, wrong = check_policy(values, data_valid=data_valid)
        if wrong:
            found[CONF_AVAILABILITY_POLICY] = wrong
        data |= policy
        if found:
            texts = dict.fromkeys(describe(key, placeholders) for key in found.values())
            errors.append((line, " ".join(texts)))
            continue
        point = point_key(data)
        if point in seen:
            earlier = {"line": str(seen[point]), **placeholders}
            key = "import_repeated" if seen[point] else "already_configured"
            errors.append((line, describe(key, earlier)))
            continue
        seen[point] = line
        firsts.setdefault(data[CONF_NAME], line)
        points.append(data)
        lines[id(data)] = line
        if assumed is not None and _data_type(client, values[CONF_ADDRESS], cells)[1]:
            assumed.append((line, describe("import_type_assumed", placeholders)))
    for name, key, details in group_errors([*known, *points]):
        if name in firsts:
            errors.append((firsts[name], describe(key, details)))
    differs = policy_differs([*known, *points]) if not errors else []
    errors += [
        (firsts[n], describe("availability_differs", {"name": n})) for n in differs if n in firsts
    ]
    for made, conflict in [] if errors else layout_conflicts(client, [*plc], points):
        wording = {"written": conflict.point.address}
        wording["point"] = conflict.other.address if conflict.other else ""
        key = "already_configured" if conflict.key == "read_only" else conflict.key
        errors.append((lines[id(made)], describe(key, wording)))
    errors.sort(key=lambda error: error[0])
    return ([] if errors else points), errors


def _unescaped(cell: str) -> str:
    """Return a cell without the `'` export puts before text a spreadsheet would run."""
    return cell[1:] if cell.startswith("'") and cell[1:].startswith(FORMULA) else cell


def point_order(data: Mapping[str, Any]) -> tuple[list[Any], str]:
    """Return the key that orders points by name (Word 2 before Word 10), then address."""
    return natural(data[CONF_NAME]), data[CONF_ADDRESS]


def natural(text: str) -> list[Any]:
    """Return a sort key that orders the numbers in a text by value."""
    return [int(part) if part.isdigit() else part.casefold() for part in re.split(r"(\d+)", text)]


def export_points(points: Iterable[Mapping[str, Any]]) -> str:
    """Return points in the import format (a header, then one line per point, by name)."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(COLUMNS)
    for data in sorted(points, key=point_order):
        row = {**data, "unit": data.get(CONF_UNIT_OF_MEASUREMENT)}
        row[CONF_READ_ONLY] = "true" if data.get(CONF_READ_ONLY) else "false"
        row |= {key: "true" if data.get(key) else None for key in SET_FLAGS}
        writer.writerow([_cell(row.get(column)) for column in COLUMNS])
    return out.getvalue()


def _cell(value: Any) -> str:
    """Return a value as a cell: numbers in their shortest form, nothing for None.

    Text that a spreadsheet would take for a formula goes behind a `'` (import drops it).
    """
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:g}" if value == float(f"{value:g}") else repr(value)
    text = str(value)
    return f"'{text}" if isinstance(value, str) and text.startswith(FORMULA) else text
