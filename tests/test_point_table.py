"""Points as text: import of pasted tables (ours, TIA Portal, Micro/WIN SMART) and export."""

from __future__ import annotations

from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors import client_class
from custom_components.plc_bridge.point_table import export_points, parse_points

SMART = client_class("s7_smart")
S7 = client_class("s7")


def test_round_trip() -> None:
    """Export, then import: the same points, names with commas and quotes included."""
    table = (
        "name,address,data_type,platform,unit,device_class,state_class,scale,offset,min,max,"
        "step,read_only\n"
        '"Tank, north ""A""",VD100,float,sensor,°C,temperature,measurement,0.1,-5,,,,yes\n'
        "Setpoint,VW20,signed,number,,,,0.5,10,10,60,0.5,no\n"
        "Pump,Q0.0,signed,switch,,,,1,0,,,,false\n"
    )
    points, errors = parse_points(SMART, table)
    assert errors == []
    assert points[0]["name"] == 'Tank, north "A"'
    assert points[0]["scale"] == 0.1
    assert points[0]["read_only"] is True
    again, errors = parse_points(SMART, export_points(points))
    assert errors == []
    assert again == points


def test_semicolons_and_decimal_commas() -> None:
    """A European spreadsheet's copy: semicolons, decimal commas; a missing platform is guessed."""
    points, errors = parse_points(SMART, "Name;Address;Data type;Scale\nTank;VD100;float;0,1\n")
    assert errors == []
    assert points[0]["scale"] == 0.1
    assert points[0]["platform"] == "number"  # writable numeric: a control


def test_errors_by_line_and_nothing_returned() -> None:
    """Every bad line is named; no point comes back unless all are good."""
    table = (
        "name,address,data_type,read_only,scale\n"
        "Good,VW100,signed,no,1\n"
        "\n"
        "Bad address,VX100,signed,no,1\n"
        "Bad flag,VW102,signed,maybe,1\n"
        "Bad number,VW104,signed,no,ten\n"
        "Twice,VW100,signed,no,1\n"
        "Taken,VW10,signed,no,1\n"
    )
    points, errors = parse_points(SMART, table, {Point("VW10", "signed")})
    assert points == []
    assert [line for line, _ in errors] == [4, 5, 6, 7, 8]
    assert "address: invalid_address" in errors[0][1]
    assert "maybe" in errors[1][1]
    assert "ten" in errors[2][1]
    assert "already a point" in errors[3][1]


def test_header_required() -> None:
    """A table without name and address columns is refused on its first line."""
    assert parse_points(SMART, "VW100,signed\n") == (
        [],
        [(1, "the first line must be a header naming at least name and address")],
    )


def test_micro_win_smart_symbol_table() -> None:
    """Symbol, Address, Comment (tab separated): words as signed integers, bits as switches."""
    table = "Symbol\tAddress\tComment\nLevel\tVW10\tTank level\nPump\tQ0.0\tMain pump\n"
    points, errors = parse_points(SMART, table)
    assert errors == []
    assert [(p["name"], p["address"], p["data_type"], p["platform"]) for p in points] == [
        ("Level", "VW10", "signed", "number"),
        ("Pump", "Q0.0", "signed", "switch"),
    ]


def test_tia_portal_tag_table() -> None:
    """Name, Path, Data Type, Logical Address, Comment: the % goes, the S7 parser checks."""
    table = (
        "Name\tPath\tData Type\tLogical Address\tComment\n"
        "Temperature\tDefault tag table\tReal\t%DB1.DBD0\t\n"
        "Label\tDefault tag table\tString[20]\t%DB1.DBB10\t\n"
        "Door\tDefault tag table\tBool\t%I0.0\t\n"
    )
    points, errors = parse_points(S7, table)
    assert errors == []
    assert [(p["address"], p["data_type"]) for p in points] == [
        ("DB1.DBD0", "REAL"),
        ("DB1.DBB10", "STRING[20]"),
        ("I0.0", "BOOL"),
    ]


def test_500_lines_at_once() -> None:
    """500 lines parse in one call."""
    table = "name,address,data_type\n" + "\n".join(f"Word {i},VW{2 * i},signed" for i in range(500))
    points, errors = parse_points(SMART, table)
    assert errors == []
    assert len(points) == 500
