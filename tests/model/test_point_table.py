"""Points as text: import of pasted tables (ours, TIA Portal, Micro/WIN SMART) and export."""

from __future__ import annotations

from collections.abc import Mapping
import time

import pytest

from custom_components.plc_bridge.model.point_table import (
    COLUMNS,
    export_points,
    parse_points,
    point_order,
)
from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors import client_class

pytestmark = pytest.mark.no_pacing

SMART = client_class("s7_smart")
S7 = client_class("s7")
HEADER = ",".join(COLUMNS)


def keyed(key: str, placeholders: Mapping[str, str]) -> str:
    """Word a problem as its key and the placeholders it fills, to check both."""
    return f"{key} {dict(placeholders)}"


def test_round_trip() -> None:
    """Export, then import: the same points, names with commas, quotes and line breaks."""
    table = (
        f"{HEADER}\n"
        '"Tank, north ""A""",VD100,float,sensor,°C,temperature,measurement,0.1,-5,,,,yes\n'
        "Setpoint,VW20,signed,number,,,,0.5,10,10,60,0.5,no\n"
        "Pump,Q0.0,signed,switch,,,,1,0,,,,false\n"
        '"Two\nlines",VD104,float,sensor,kWh,energy,total_increasing,0.001,0,,,,1\n'
    )
    points, errors = parse_points(SMART, table)
    assert errors == []
    assert points[0]["name"] == 'Tank, north "A"'
    assert points[0]["scale"] == 0.1
    assert points[0]["read_only"] is True
    assert points[3]["name"] == "Two\nlines"
    again, errors = parse_points(SMART, export_points(points))
    assert errors == []
    assert again == sorted(points, key=point_order)
    assert export_points(again) == export_points(points)


def test_export_in_name_order_whatever_the_stored_order() -> None:
    """Points export by name (numbers by value), then address: the same text after a restart."""
    table = f"{HEADER}\nWord 10,VW10,signed\nword 2,VW2,signed\nWord 2,VW0,signed\n"
    points, errors = parse_points(SMART, table)
    assert errors == []
    exported = export_points(points)
    assert [line.split(",")[1] for line in exported.splitlines()[1:]] == ["VW0", "VW2", "VW10"]
    assert export_points(reversed(points)) == exported


def test_semicolons_and_decimal_commas() -> None:
    """A European spreadsheet's copy: semicolons, decimal commas; no platform: a sensor."""
    points, errors = parse_points(SMART, "Name;Address;Data type;Scale\nTank;VD100;float;0,1\n")
    assert errors == []
    assert points[0]["scale"] == 0.1
    assert (points[0]["platform"], points[0]["read_only"]) == ("sensor", True)


def test_errors_by_line_and_nothing_returned() -> None:
    """Every bad line is named by its number in the paste; no point unless all are good."""
    table = (
        "\ufeffname,address,data_type,read_only,scale\n"
        "Good,VW100,signed,no,1\n"
        "\n"
        "Bad address,VX100,signed,no,1\n"
        "Bad flag,VW102,signed,maybe,1\n"
        "Bad number,VW104,signed,no,ten\n"
        "Twice,VW100,signed,no,1\n"
        "Taken,VW10,signed,no,1\n"
        "Zero scale,VW106,signed,no,0\n"
    )
    points, errors = parse_points(SMART, table, {Point("VW10", "signed")}, keyed)
    assert points == []
    assert [line for line, _ in errors] == [4, 5, 6, 7, 8, 9]
    assert errors[0][1].startswith("invalid_address {'error': \"'VX100' is not")
    assert errors[1][1] == "import_not_yes_or_no {'column': 'read_only', 'text': 'maybe'}"
    assert errors[2][1] == "import_not_a_number {'column': 'scale', 'text': 'ten'}"
    assert errors[3][1].startswith("import_repeated {'line': '2', 'address': 'VW100'")
    assert errors[4][1].startswith("already_configured")
    assert errors[5][1].startswith("scale_zero")


def test_class_unit_and_state_class_checked_per_line() -> None:
    """The form's checks refuse a line: a number with a timestamp class, a unit off its class."""
    table = (
        "name,address,data_type,platform,unit,device_class,state_class\n"
        "A,VD100,float,sensor,,timestamp,\n"
        "B,VD104,float,sensor,bar,temperature,\n"
        "C,VD108,float,sensor,°C,temperature,total_increasing\n"
        "D,VD112,float,sensor,°C,temperature,measurement\n"
    )
    _, errors = parse_points(SMART, table, describe=lambda key, _: key)
    assert errors == [
        (2, "invalid_device_class"),
        (3, "unit_not_valid"),
        (4, "state_class_not_valid"),
    ]


@pytest.mark.parametrize(
    ("text", "problem"),
    [("VW100,signed\n", "import_no_header"), ("name,address\n\n", "import_no_points")],
)
def test_header_and_lines_required(text: str, problem: str) -> None:
    """A table without name and address columns, or without lines, is refused on line 1."""
    assert parse_points(SMART, text, describe=lambda key, _: key) == ([], [(1, problem)])


def test_blank_lines_before_the_header_keep_line_numbers() -> None:
    """Line numbers are those of the paste, blank lines and line breaks in cells counted."""
    table = '\n\nname,address\n"Multi\nline",VW100\nBad,VX1\n'
    _, errors = parse_points(SMART, table, describe=lambda key, _: key)
    assert errors == [(6, "invalid_address")]


def test_micro_win_smart_symbol_table() -> None:
    """Symbol, Address, Comment (tab separated): words signed whatever the comment; read only."""
    table = (
        "Symbol\tAddress\tComment\n"
        "Level\tVW10\tTank level\n"
        "Pump\tQ0.0\tMain pump\n"
        "Outside\tVD100\tOutside temperature (REAL)\n"
        "Count\tVD104\tunsigned counter\n"
        "Always_On\tSM0.0\tAlways on\n"
    )
    points, errors = parse_points(SMART, table)
    assert errors == []
    assert [(p["name"], p["address"], p["data_type"], p["platform"]) for p in points] == [
        ("Level", "VW10", "signed", "sensor"),
        ("Pump", "Q0.0", "signed", "binary_sensor"),
        ("Outside", "VD100", "signed", "sensor"),
        ("Count", "VD104", "signed", "sensor"),
        ("Always_On", "SM0.0", "signed", "binary_sensor"),
    ]


def test_tia_portal_tag_table() -> None:
    """Name, Path, Data Type, Logical Address, Comment: the % goes, the S7 parser checks."""
    table = (
        "Name\tPath\tData Type\tLogical Address\tComment\tHmi Visible\n"
        "Temperature\tDefault tag table\tReal\t%DB1.DBD0\t\tTrue\n"
        "Label\tDefault tag table\tString[20]\t%DB1.DBB10\t\tTrue\n"
        "Door\tDefault tag table\tBool\t%I0.0\tFront door\tTrue\n"
        "Speed\tMotors\tInt\t%MW20\t\tTrue\n"
    )
    points, errors = parse_points(S7, table)
    assert errors == []
    assert [(p["address"], p["data_type"], p["platform"]) for p in points] == [
        ("DB1.DBD0", "REAL", "sensor"),
        ("DB1.DBB10", "STRING[20]", "sensor"),
        ("I0.0", "BOOL", "binary_sensor"),
        ("MW20", "INT", "sensor"),
    ]


def test_tia_portal_in_german() -> None:
    """A German TIA Portal's headers: Name, Pfad, Datentyp, Logische Adresse, Kommentar."""
    table = "Name;Pfad;Datentyp;Logische Adresse;Kommentar\nDruck;Standard;Real;%MD8;bar\n"
    points, errors = parse_points(S7, table)
    assert errors == []
    assert [(p["name"], p["address"], p["data_type"]) for p in points] == [("Druck", "MD8", "REAL")]


def test_tia_type_refused_by_the_parser() -> None:
    """A TIA type the S7 client cannot read is named on its line with the parser's words."""
    table = "Name\tData Type\tLogical Address\nT\tLTime\t%MB4\n"
    _, errors = parse_points(S7, table)
    assert errors[0][0] == 2
    assert "LTIME" in errors[0][1].upper()
    points, _ = parse_points(S7, table.replace("LTime\t%MB4", "S5Time\t%MW6"))
    assert [(p["address"], p["data_type"]) for p in points] == [("MW6", "S5TIME")]


def test_s7_type_from_the_address() -> None:
    """No type column: the address's width decides (bit BOOL, byte BYTE, word INT, dword DINT)."""
    table = "name,address\nA,M0.1\nB,MB1\nC,MW2\nD,DB1.DBD4\n"
    points, errors = parse_points(S7, table)
    assert errors == []
    assert [p["data_type"] for p in points] == ["BOOL", "BYTE", "INT", "DINT"]


def test_500_lines_at_once() -> None:
    """500 lines parse in one call, quickly, and export back line for line."""
    table = "name,address,data_type\n" + "\n".join(f"Word {i},VW{2 * i},signed" for i in range(500))
    start = time.perf_counter()
    points, errors = parse_points(SMART, table)
    assert time.perf_counter() - start < 2
    assert errors == []
    assert len(points) == 500
    assert len(export_points(points).splitlines()) == 501


def test_durations_shown_as_text_round_trip() -> None:
    """A Tecomat TIME shown as text (as an upgrade keeps one) stays text through the table."""
    tecomat = client_class("tecomat")
    table = "name,address,data_type,platform,as_text\nRun time,plcData.runTime,TIME,sensor,yes\n"
    points, errors = parse_points(tecomat, table)
    assert errors == []
    assert points[0]["as_text"] is True
    again, errors = parse_points(tecomat, export_points(points))
    assert errors == []
    assert again == points
    plain, errors = parse_points(tecomat, table.replace(",yes\n", ",\n"))
    assert errors == []
    assert "as_text" not in plain[0]
