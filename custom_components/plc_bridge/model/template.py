"""Machines made from one: a template (count, stride or counting name part, name pattern).

"Add machines like this one" makes copies of a machine (device subentry): each copy is a
machine of its own (its own device) with every point of the original, composites, data-valid
address and poll classes included, its addresses moved by its vendor (`PlcClient.shift_point`:
copy k by k strides) and named by the pattern ("Shutter {n}": the original is number 1, its
copies 2, 3, ...). Every moved point passes the checks a form makes (a valid address, writable
where its entity writes, no write into read-only data) and may not overlap data of another
machine or copy; the first that fails refuses them all, before anything is stored.

The original keeps the record (`template`: id, count of copies, stride, unit, counting part,
name pattern); each copy says which copy it is (`copy_of`: the template id and its number).
The PLC file carries both, and a pasted file makes the copies it names but does not hold.
A copy is made once: editing the original later changes the original only (its copies keep
their points, and the record says how they were made); more copies continue the numbering.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
import secrets
from typing import Any, Final

from homeassistant.const import CONF_NAME

from ..const import (
    CONF_ADDRESS,
    CONF_DATA_TYPE,
    CONF_ENTITY,
    CONF_PLATFORM,
    CONF_POINTS,
    CONF_ROLE,
)
from ..plc import Footprint, PlcClient, PlcError, Point
from ..plc.shifting import NAME
from .availability import CONF_AVAILABILITY_ADDRESS, CONF_AVAILABILITY_DATA_TYPE
from .composite import as_platform, assign_entities
from .points import check_point
from .write_rules import layout_conflicts

CONF_TEMPLATE: Final = "template"
"""Data of a machine that copies were made from: how they were made."""
CONF_COPY_OF: Final = "copy_of"
"""Data of a copy: the template's id and the copy's number (the original is number 1)."""
CONF_TEMPLATE_ID: Final = "id"
CONF_COUNT: Final = "count"
CONF_STRIDE: Final = "stride"
CONF_UNIT: Final = "unit"
CONF_PART: Final = "part"
CONF_NAME_PATTERN: Final = "name"
CONF_NUMBER: Final = "number"
NUMBER_MARK: Final = "{n}"
MAX_COPIES: Final = 255
"""The most copies one template makes at once (the form's bound)."""
MAX_RECORDED: Final = 4096
"""The most copies a template's record may count (a pasted file's)."""
TEMPLATE_KEYS: Final = {
    CONF_TEMPLATE_ID: str,
    CONF_COUNT: int,
    CONF_STRIDE: int,
    CONF_UNIT: str,
    CONF_PART: str,
    CONF_NAME_PATTERN: str,
}
COPY_KEYS: Final = {CONF_TEMPLATE_ID: str, CONF_NUMBER: int}


class TemplateError(ValueError):
    """Copies that cannot be made: the form field at fault, the copy's number, the reason."""

    def __init__(self, field: str, message: str, copy: int = 0) -> None:
        """Keep the field, the copy (0: none in particular) and the reason in plain words."""
        super().__init__(message)
        self.field = field
        self.copy = copy


@dataclass(frozen=True, slots=True, kw_only=True)
class Template:
    """How the copies of a machine are made; `count` copies exist (numbers 2 to count + 1)."""

    template_id: str
    count: int
    stride: int
    unit: str
    part: str = ""
    name: str

    def as_data(self) -> dict[str, Any]:
        """Return the record as the original machine stores it."""
        data: dict[str, Any] = {
            CONF_TEMPLATE_ID: self.template_id,
            CONF_COUNT: self.count,
            CONF_STRIDE: self.stride,
            CONF_UNIT: self.unit,
            CONF_NAME_PATTERN: self.name,
        }
        if self.part:
            data[CONF_PART] = self.part
        return data

    @classmethod
    def from_data(cls, data: Mapping[str, Any]) -> Template:
        """Return the record a machine stores."""
        return cls(
            template_id=str(data[CONF_TEMPLATE_ID]),
            count=int(data[CONF_COUNT]),
            stride=int(data[CONF_STRIDE]),
            unit=str(data[CONF_UNIT]),
            part=str(data.get(CONF_PART, "")),
            name=str(data[CONF_NAME_PATTERN]),
        )

    @property
    def field(self) -> str:
        """The form field that says how copies move: the stride, or the part of the names."""
        return CONF_PART if self.unit == NAME else CONF_STRIDE

    def title(self, number: int) -> str:
        """Return the name of machine `number` of the series (the original is 1)."""
        return self.name.replace(NUMBER_MARK, str(number))


def record_error(data: Any, keys: Mapping[str, type]) -> str | None:
    """Return the first key of a stored record that is missing or of the wrong kind, if any."""
    if not isinstance(data, Mapping):
        return ""
    for key in data:
        if key not in keys:
            return str(key)
    for key, kind in keys.items():
        value = data.get(key)
        if key == CONF_PART and value is None:
            continue
        if isinstance(value, bool) or not isinstance(value, kind):
            return key
    return None


def record_problem(client: type[PlcClient], template: Template) -> str | None:
    """Return why a stored record (a pasted file's) cannot make copies; None where it can."""
    if template.unit not in client.shift_units:
        return f"this PLC's addresses do not move by {template.unit}"
    if template.unit == NAME and not template.part:
        return "it names no part of the variable names that counts"
    if NUMBER_MARK not in template.name:
        return f"its names need {NUMBER_MARK}"
    if template.stride == 0 or not 0 <= template.count <= MAX_RECORDED:
        return f"it needs a stride other than 0 and 0 to {MAX_RECORDED} copies"
    return None


def new_template(
    client: type[PlcClient], stored: Mapping[str, Any] | None, values: Mapping[str, Any]
) -> Template:
    """Return the template a form asks for; more copies of a template continue its record.

    Raise TemplateError on the field at fault: a unit the vendor has not, no counting part
    where names count, a name pattern without {n}, a stride other than the record's.
    """
    unit = str(values.get(CONF_UNIT) or client.shift_units[0])
    if unit not in client.shift_units:
        raise TemplateError(CONF_UNIT, f"this PLC's addresses do not move by {unit}")
    part = str(values.get(CONF_PART) or "").strip() if unit == NAME else ""
    if unit == NAME and not part:
        raise TemplateError(CONF_PART, "name the part of the variable names that counts")
    name = str(values.get(CONF_NAME_PATTERN, "")).strip()
    if NUMBER_MARK not in name:
        raise TemplateError(CONF_NAME_PATTERN, f"the names need {NUMBER_MARK}")
    count, stride = int(values[CONF_COUNT]), int(values[CONF_STRIDE])
    if not 1 <= count <= MAX_COPIES:
        raise TemplateError(CONF_COUNT, f"make 1 to {MAX_COPIES} copies at once")
    if stride == 0:
        raise TemplateError(CONF_STRIDE, "a stride of 0 puts every copy on the original")
    if not stored:
        return Template(
            template_id=secrets.token_hex(6),
            count=0,
            stride=stride,
            unit=unit,
            part=part,
            name=name,
        )
    before = Template.from_data(stored)
    if (before.stride, before.unit, before.part) != (stride, unit, part):
        raise TemplateError(
            CONF_STRIDE,
            f"the copies so far moved by {before.stride} {before.unit}"
            + (f" of {before.part}" if before.part else "")
            + "; more copies move by the same",
        )
    return Template(
        template_id=before.template_id,
        count=before.count,
        stride=stride,
        unit=unit,
        part=part,
        name=name,
    )


@dataclass(frozen=True, slots=True)
class Copy:
    """One copy to store: its number in the series, its name and its machine's data."""

    number: int
    title: str
    data: dict[str, Any]


def make_copies(
    client: type[PlcClient],
    template: Template,
    original: Mapping[str, Any],
    count: int,
    plc: Iterable[tuple[str, Mapping[str, Any]]],
    *,
    numbers: Iterable[int] | None = None,
) -> list[Copy]:
    """Return `count` more copies of the original machine's data, checked; raise TemplateError.

    `plc` is every other machine of the PLC (its name and data, the original included);
    `numbers` the copies to make (default: the `count` after the template's). Nothing is
    stored here: the caller stores all or, on an error, none.
    """
    machines = list(plc)
    taken_names = {title.casefold() for title, _ in machines}
    wanted = list(numbers) if numbers is not None else []
    if numbers is None:
        wanted = list(range(template.count + 2, template.count + 2 + count))
    known = list(machines)
    copies: list[Copy] = []
    for number in wanted:
        title = template.title(number)
        if title.casefold() in taken_names:
            raise TemplateError(CONF_NAME_PATTERN, f"another machine is named {title}", number)
        taken_names.add(title.casefold())
        made = Copy(number, title, _copy_data(client, template, original, number))
        _check_copy(client, known, made, template.field)
        made.data[CONF_COPY_OF] = {CONF_TEMPLATE_ID: template.template_id, CONF_NUMBER: number}
        copies.append(made)
        known.append((title, made.data))
    return copies


def _copy_data(
    client: type[PlcClient], template: Template, original: Mapping[str, Any], number: int
) -> dict[str, Any]:
    """Return the original's data for copy `number`: addresses moved, new point ids, no record."""
    data = {
        key: value for key, value in original.items() if key not in (CONF_TEMPLATE, CONF_COPY_OF)
    }
    points: dict[str, dict[str, Any]] = {}
    for point_data in original.get(CONF_POINTS, {}).values():
        moved = dict(point_data)
        moved.pop(CONF_ENTITY, None)
        moved[CONF_ADDRESS] = _moved(client, template, point_data, number)
        points[secrets.token_hex(6)] = moved
    assign_entities(points)
    data[CONF_POINTS] = points
    if original.get(CONF_AVAILABILITY_ADDRESS):
        where = {
            CONF_ADDRESS: original[CONF_AVAILABILITY_ADDRESS],
            CONF_DATA_TYPE: original.get(CONF_AVAILABILITY_DATA_TYPE, ""),
        }
        data[CONF_AVAILABILITY_ADDRESS] = _moved(client, template, where, number)
    return data


def _moved(
    client: type[PlcClient], template: Template, point_data: Mapping[str, Any], number: int
) -> str:
    """Return a stored point's address moved by its vendor for copy `number`."""
    by = (number - 1) * template.stride
    try:
        point = client.validate_point(
            Point(str(point_data[CONF_ADDRESS]), str(point_data[CONF_DATA_TYPE]))
        )
        return client.shift_point(point, by, template.unit, template.part).address
    except PlcError as err:
        raise TemplateError(template.field, str(err), number) from err


def _check_copy(
    client: type[PlcClient], known: list[tuple[str, Mapping[str, Any]]], made: Copy, field: str
) -> None:
    """Refuse a copy a form would refuse, or whose data overlaps another machine's."""
    title, data, number = made.title, made.data, made.number
    new = list(data[CONF_POINTS].values())
    for point_data in new:
        platform = as_platform(str(point_data.get(CONF_PLATFORM, "")), point_data.get(CONF_ROLE))
        _, _, errors, _ = check_point(client, {**point_data, CONF_PLATFORM: platform})
        if errors:
            raise TemplateError(
                field, f"{point_data[CONF_ADDRESS]} does not fit its entity there", number
            )
    others = [(other, point_data) for other, machine in known for point_data in _addressed(machine)]
    covered = [(other, point_data, _footprint(client, point_data)) for other, point_data in others]
    for point_data in _addressed(data):
        mine = _footprint(client, point_data)
        for other, theirs, footprint in covered:
            if mine is not None and footprint is not None and mine.overlaps(footprint):
                raise TemplateError(
                    field,
                    f"{point_data[CONF_ADDRESS]} of {title} overlaps {theirs[CONF_ADDRESS]} "
                    f"of {other}",
                    number,
                )
    plc_points = [point_data for _, point_data in others if CONF_NAME in point_data]
    for point_data, conflict in layout_conflicts(client, plc_points, new)[:1]:
        other = conflict.other.address if conflict.other else conflict.point.address
        raise TemplateError(
            field,
            f"{point_data[CONF_ADDRESS]} of {title} would write data of the read-only point "
            f"{other}",
            number,
        )


def _addressed(machine: Mapping[str, Any]) -> list[Mapping[str, Any]]:
    """Return every address a machine's data names: its points and its data-valid address."""
    found: list[Mapping[str, Any]] = list(machine.get(CONF_POINTS, {}).values())
    if machine.get(CONF_AVAILABILITY_ADDRESS):
        found.append(
            {
                CONF_ADDRESS: machine[CONF_AVAILABILITY_ADDRESS],
                CONF_DATA_TYPE: machine.get(CONF_AVAILABILITY_DATA_TYPE, ""),
            }
        )
    return found


def _footprint(client: type[PlcClient], point_data: Mapping[str, Any]) -> Footprint | None:
    """What a stored point covers; None for one its vendor cannot parse (its parser's to refuse)."""
    try:
        point = client.validate_point(
            Point(str(point_data[CONF_ADDRESS]), str(point_data[CONF_DATA_TYPE]))
        )
        return client.footprint(point)
    except PlcError:
        return None
