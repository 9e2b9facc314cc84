"""Points as text: pasted tables imported line by line, and the same format exported.

The format is CSV with a header row (comma, semicolon or tab separated, as engineering tools
and spreadsheets copy tables). A TIA Portal tag table or a STEP 7-Micro/WIN SMART symbol table
is told by its headers. Every line is checked by the same `point_data` as the forms.
"""

from __future__ import annotations

from collections.abc import Collection, Iterable, Mapping
import csv
import io
import re
from typing import Any

from homeassistant.components.sensor import CONF_STATE_CLASS
from homeassistant.const import CONF_DEVICE_CLASS, CONF_NAME, CONF_UNIT_OF_MEASUREMENT

from .const import (
    CONF_ADDRESS,
    CONF_DATA_TYPE,
    CONF_MAX,
    CONF_MIN,
    CONF_OFFSET,
    CONF_PLATFORM,
    CONF_READ_ONLY,
    CONF_SCALE,
    CONF_STEP,
)
from .plc import PlcClient, Point
from .point_form import point_data, suggested_platform

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
)
"""The columns of the format, in the order export writes them."""
HEADERS: dict[str, str] = {
    **{column: column for column in COLUMNS},
    "unit_of_measurement": "unit",
    "type": CONF_DATA_TYPE,
    "datatype": CONF_DATA_TYPE,
    "entity_type": CONF_PLATFORM,
    "readonly": CONF_READ_ONLY,
    # TIA Portal tag tables: Name, Path, Data Type, Logical Address, Comment, ...
    "logical_address": CONF_ADDRESS,
    # STEP 7-Micro/WIN SMART symbol tables: Symbol, Address, Comment.
    "symbol": CONF_NAME,
}
"""Header names (lower case, spaces as underscores) and the column each one means."""
NUMBERS = (CONF_SCALE, CONF_OFFSET, CONF_MIN, CONF_MAX, CONF_STEP)
TRUE = {"1", "true", "yes", "y", "on", "x"}
FALSE = {"", "0", "false", "no", "n", "off"}
SMART_SIZES = re.compile(r"^[A-Z]+(B|W|D)\d", re.IGNORECASE)


def _header(text: str) -> str:
    """Return a header cell as a key of HEADERS."""
    return re.sub(r"[\s-]+", "_", text.strip().lower())


def _rows(text: str) -> tuple[list[str], list[tuple[int, list[str]]]]:
    """Split pasted text into its header and its numbered rows (blank lines dropped)."""
    lines = text.strip("\n").splitlines()
    first = lines[0] if lines else ""
    delimiter = max(("\t", ";", ","), key=first.count)
    rows = list(csv.reader(io.StringIO("\n".join(lines)), delimiter=delimiter))
    numbered = [
        (number, row) for number, row in enumerate(rows[1:], 2) if any(c.strip() for c in row)
    ]
    return (rows[0] if rows else []), numbered


def _flag(text: str) -> bool | None:
    """Return a yes/no cell as a bool, or None when it is neither."""
    word = text.strip().lower()
    return True if word in TRUE else False if word in FALSE else None


def _values(client: type[PlcClient], cells: Mapping[str, str]) -> tuple[dict[str, Any], str]:
    """Return a row as the values point_data takes, or an error for a cell it cannot read."""
    values: dict[str, Any] = {CONF_NAME: cells.get(CONF_NAME, "").strip()}
    address = cells.get(CONF_ADDRESS, "").strip().lstrip("%")
    values[CONF_ADDRESS] = address
    data_type = cells.get(CONF_DATA_TYPE, "").strip()
    if not data_type:
        # A symbol table names no type: a byte, word or double word is read as signed.
        smart = SMART_SIZES.match(address) and "signed" in client.data_types
        data_type = "signed" if smart else client.data_types[0]
    values[CONF_DATA_TYPE] = data_type
    for key in NUMBERS:
        text = cells.get(key, "").strip()
        if text:
            try:
                values[key] = float(text.replace(",", "."))  # a decimal comma too
            except ValueError:
                return {}, f"{key}: '{text}' is not a number"
    read_only = _flag(cells.get(CONF_READ_ONLY, ""))
    if read_only is None:
        return {}, f"read_only: '{cells[CONF_READ_ONLY].strip()}' is not yes or no"
    values[CONF_READ_ONLY] = read_only
    for key, column in (
        (CONF_UNIT_OF_MEASUREMENT, "unit"),
        (CONF_DEVICE_CLASS, CONF_DEVICE_CLASS),
        (CONF_STATE_CLASS, CONF_STATE_CLASS),
    ):
        if cells.get(column, "").strip():
            values[key] = cells[column].strip()
    platform = cells.get(CONF_PLATFORM, "").strip().lower().replace(" ", "_")
    values[CONF_PLATFORM] = platform or suggested_platform(
        client, address, data_type, read_only=read_only
    )
    return values, ""


def parse_points(
    client: type[PlcClient], text: str, taken: Collection[Point] = ()
) -> tuple[list[dict[str, Any]], list[tuple[int, str]]]:
    """Return the points of a pasted table and the errors by line; no points unless no errors.

    `taken` holds the points already configured: a line naming one again is an error, as is a
    line repeating an earlier line's address and data type.
    """
    header, rows = _rows(text)
    columns = [HEADERS.get(_header(cell)) for cell in header]
    if CONF_NAME not in columns or CONF_ADDRESS not in columns:
        return [], [(1, "the first line must be a header naming at least name and address")]
    points: list[dict[str, Any]] = []
    errors: list[tuple[int, str]] = []
    seen = set(taken)
    for number, row in rows:
        cells = {
            column: cell for column, cell in zip(columns, row, strict=False) if column is not None
        }
        values, problem = _values(client, cells)
        if problem:
            errors.append((number, problem))
            continue
        data, field_errors, placeholders = point_data(client, values)
        if field_errors:
            detail = placeholders.get("error", "")
            errors.append(
                (
                    number,
                    "; ".join(f"{field}: {key}" for field, key in field_errors.items())
                    + (f" ({detail})" if detail else ""),
                )
            )
            continue
        point = Point(data[CONF_ADDRESS], data[CONF_DATA_TYPE])
        if point in seen:
            errors.append((number, f"{point.address} ({point.data_type}) is already a point"))
            continue
        seen.add(point)
        points.append(data)
    if not rows:
        errors.append((1, "no point follows the header"))
    return ([] if errors else points), errors


def export_points(points: Iterable[Mapping[str, Any]]) -> str:
    """Return points in the import format (a header, then one line per point)."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(COLUMNS)
    for data in points:
        row = {**data, "unit": data.get(CONF_UNIT_OF_MEASUREMENT, "")}
        writer.writerow(
            [
                ("true" if row.get(column) else "false")
                if column == CONF_READ_ONLY
                else _cell(row.get(column))
                for column in COLUMNS
            ]
        )
    return out.getvalue()


def _cell(value: Any) -> str:
    """Return a value as a cell: numbers in their shortest form, nothing for None."""
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:g}" if value == float(f"{value:g}") else repr(value)
    return str(value)
