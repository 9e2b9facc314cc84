"""The benchmarks' points: a realistic mix per vendor, and the request count it should take."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
import math

from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors import client_class


def _memory_mix(count: int, kinds: tuple[tuple[str, str], ...]) -> list[Point]:
    """A realistic mix laid out in one memory area: a REAL, an INT, a bit and a byte in turn.

    `kinds` gives each one's address (with `{offset}` and, for the bit, `{bit}`) and data type.
    """
    points: list[Point] = []
    offset = 0
    for index in range(count):
        address, data_type = kinds[index % 4]
        points.append(Point(address.format(offset=offset, bit=index % 8), data_type))
        offset += (4, 2, 1, 1)[index % 4]
    return points


def s7_smart_points(count: int) -> list[Point]:
    """A realistic mix laid out in V memory: REALs, INTs, bits and bytes."""
    return _memory_mix(
        count,
        (
            ("VD{offset}", "float"),
            ("VW{offset}", "signed"),
            ("V{offset}.{bit}", "signed"),
            ("VB{offset}", "unsigned"),
        ),
    )


def tecomat_points(count: int) -> list[Point]:
    """Variables named as the Tecomat simulator is expected to publish them (adjust with it)."""
    return [Point(f"BENCH.V{index}", "INT") for index in range(count)]


def s7_points(count: int) -> list[Point]:
    """The same mix as for the S7-200 SMART, laid out in data block 1."""
    return _memory_mix(
        count,
        (
            ("DB1.DBD{offset}", "REAL"),
            ("DB1.DBW{offset}", "INT"),
            ("DB1.DBX{offset}.{bit}", "BOOL"),
            ("DB1.DBB{offset}", "BYTE"),
        ),
    )


def softplc_points(count: int) -> list[Point]:
    """A mix in the SoftPLC simulator's bench files: words, floats, bits, timer words, gaps.

    Every fifth word of N10 is skipped and F11 is read at every third element, so that the
    planner's merging of nearby elements shows in the `<data>` items per poll.
    """
    points: list[Point] = []
    for index in range(count):
        match index % 4:
            case 0:
                points.append(Point(f"N10:{index // 4 * 5 // 4}", "INT"))
            case 1:
                points.append(Point(f"F11:{index * 3 % 1000}", "REAL"))
            case 2:
                points.append(Point(f"B12:{index // 16}/{index % 16}", "BOOL"))
            case _:
                points.append(Point(f"T13:{index}.ACC", "INT"))
    return points


def plcnext_points(count: int) -> list[Point]:
    """The DINT variables the PLCnext simulator's bench option publishes (Bench.Value<i>)."""
    return [Point(f"Bench.Value{index}", "DINT") for index in range(count)]


@dataclass(frozen=True, slots=True)
class Vendor:
    """How to benchmark one vendor: its points and the request count its planner promises."""

    points: Callable[[int], list[Point]]
    target: Callable[[int], int] | None
    target_text: str
    items: Callable[[list[Point]], int] | None = None  # items a poll asks for, where counted


VENDORS: dict[str, Vendor] = {
    "s7_smart": Vendor(s7_smart_points, lambda n: math.ceil(n / 32), "ceil(N/32)"),
    "tecomat": Vendor(tecomat_points, None, "URI <= 256 chars"),
    "s7": Vendor(s7_points, None, "PDU-packed"),
    "plcnext": Vendor(plcnext_points, lambda n: 1 if n else 0, "1 group read"),
    "softplc": Vendor(
        softplc_points,
        lambda n: 1 if n else 0,
        "1 POST",
        lambda points: client_class("softplc").items_for(points),  # type: ignore[attr-defined]
    ),
}
