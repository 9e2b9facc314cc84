"""Points exported as a table: the import's format, one line per point, ordered by name."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
import csv
import io
from typing import Any

from homeassistant.const import CONF_UNIT_OF_MEASUREMENT

from .const import CONF_READ_ONLY
from .point_table import COLUMNS, FORMULA, SET_FLAGS, point_order


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
