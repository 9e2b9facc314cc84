"""Imported tables: controls only where asked, inputs never, no type from comments, safe CSV."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from homeassistant.core import HomeAssistant
from homeassistant.helpers import issue_registry as ir
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import DOMAIN
from custom_components.plc_bridge.model.point_table import (
    COLUMNS,
    export_points,
    parse_points,
    point_order,
)
from custom_components.plc_bridge.model.points import check_point
from custom_components.plc_bridge.plc.vendors import client_class
from custom_components.plc_bridge.runtime.issues import async_check_tls
from simulators.tecomat import TecomatSimulator
from tests.entries import unload_all
from tests.harness import make_tecomat_entry

pytestmark = pytest.mark.no_pacing

SMART = client_class("s7_smart")
S7 = client_class("s7")


def rows(points: list[dict[str, Any]]) -> list[tuple[str, str, str, bool]]:
    """Each point's address, data type, platform and read-only flag."""
    return [(p["address"], p["data_type"], p["platform"], p["read_only"]) for p in points]


def keyed(key: str, placeholders: Mapping[str, str]) -> str:
    """Word a problem as its key and the address and type it names."""
    return f"{key} {placeholders.get('address', '')} {placeholders.get('data_type', '')}".strip()


def test_micro_win_inputs_and_words_read_only() -> None:
    """A symbol table without read_only: inputs, outputs and words become read-only sensors."""
    table = "Symbol\tAddress\tComment\nDoor\tI0.0\tFront door\nLevel\tVW10\tTank\nPump\tQ0.0\t\n"
    points, errors = parse_points(SMART, table)
    assert errors == []
    assert rows(points) == [
        ("I0.0", "signed", "binary_sensor", True),
        ("VW10", "signed", "sensor", True),
        ("Q0.0", "signed", "binary_sensor", True),
    ]


def test_a_control_where_the_row_asks_for_one() -> None:
    """A platform column asking for a switch or number gives a writable control."""
    table = "name,address,platform\nPump,Q0.0,switch\nSet,VW20,number\nLevel,VW22,sensor\n"
    points, errors = parse_points(SMART, table)
    assert errors == []
    assert rows(points) == [
        ("Q0.0", "signed", "switch", False),
        ("VW20", "signed", "number", False),
        ("VW22", "signed", "sensor", True),
    ]


@pytest.mark.parametrize(
    ("vendor", "address"), [("s7_smart", "I0.0"), ("s7_smart", "AIW16"), ("s7", "%I0.1")]
)
def test_no_control_on_an_input(vendor: str, address: str) -> None:
    """A row asking for a control on an input is refused on its line."""
    platform = "switch" if "." in address else "number"
    table = f"name,address,platform\nIn,{address},{platform}\n"
    points, errors = parse_points(client_class(vendor), table, describe=keyed)
    assert points == []
    assert errors[0][0] == 2
    assert errors[0][1].startswith("address_not_writable")


def test_point_form_refuses_a_control_on_an_input() -> None:
    """The point form refuses a switch on an input, on the entity type."""
    values = {"name": "Door", "platform": "switch", "address": "I0.0", "data_type": "signed"}
    _, _, errors, _ = check_point(SMART, values)
    assert errors == {"platform": "address_not_writable"}
    _, _, errors, _ = check_point(SMART, {**values, "platform": "binary_sensor"})
    assert errors == {}


@pytest.mark.parametrize(
    "header",
    [
        "Hmi Writeable",
        "Writable from HMI/OPC UA/Web API",
        "Schreibbar aus HMI/OPC UA/Web API",
    ],
)
def test_tia_not_writable_flag_honoured(header: str) -> None:
    """A TIA Portal tag not writable from HMI is read only, even where a platform asks more."""
    table = (
        f"Name\tData Type\tLogical Address\tplatform\t{header}\n"
        "Speed\tInt\t%MW20\tnumber\tFalse\n"
        "Setpoint\tInt\t%MW22\tnumber\tTrue\n"
    )
    points, errors = parse_points(S7, table)
    assert errors == []
    assert [p["read_only"] for p in points] == [True, False]


def test_comment_never_chooses_the_type() -> None:
    """AIW16 "raw analog input" is a signed word, and the line says the type was assumed."""
    table = "Symbol\tAddress\tComment\nAI\tAIW16\traw analog input\nOut\tVD100\tREAL value\n"
    assumed: list[tuple[int, str]] = []
    points, errors = parse_points(SMART, table, describe=keyed, assumed=assumed)
    assert errors == []
    assert [p["data_type"] for p in points] == ["signed", "signed"]
    assert assumed == [
        (2, "import_type_assumed AIW16 signed"),
        (3, "import_type_assumed VD100 signed"),
    ]


def test_no_assumption_where_the_type_is_given_or_changes_nothing() -> None:
    """A named type, or a bit (a BOOL whatever the mode), needs no note."""
    table = "name,address,data_type\nA,VW10,unsigned\nB,Q0.1,\n"
    assumed: list[tuple[int, str]] = []
    points, errors = parse_points(SMART, table, assumed=assumed)
    assert (len(points), errors, assumed) == (2, [], [])


def test_export_escapes_formulas_and_round_trips() -> None:
    """Text cells a spreadsheet would run get a leading `'`; numbers stay; import undoes it."""
    table = (
        f"{','.join(COLUMNS)}\n"
        '"\'=HYPERLINK(""http://x"")",VW10,signed,sensor,,,,1,-5,,,,yes\n'
        "'+1 pump,VW12,signed,number,,,,0.5,-2.5,-10,10,,no\n"
        "'-x,VW14,signed,sensor,'@unit,,,1,0,,,,yes\n"
        "''quoted,VW16,signed,sensor,,,,1,0,,,,yes\n"
    )
    points, errors = parse_points(SMART, table)
    assert errors == []
    assert [p["name"] for p in points] == ['=HYPERLINK("http://x")', "+1 pump", "-x", "'quoted"]
    assert points[0]["offset"] == -5
    assert points[1]["min"] == -10
    assert points[2]["unit_of_measurement"] == "@unit"
    exported = export_points(points)
    for line in exported.splitlines()[1:]:
        assert not line.lstrip('"').startswith(("=", "+", "-", "@"))
    assert ",-5.0," not in exported
    assert ",-5," in exported
    again, errors = parse_points(SMART, exported)
    assert errors == []
    assert again == sorted(points, key=point_order)


async def test_basic_over_plain_http_raises_an_issue(
    hass: HomeAssistant, tecomat_basic_ha_sim: TecomatSimulator, issue_registry: ir.IssueRegistry
) -> None:
    """TecoApi Basic over HTTP sends the password readable: a warning until TLS or Digest."""
    entry: MockConfigEntry = make_tecomat_entry(hass, tecomat_basic_ha_sim, [])
    assert await hass.config_entries.async_setup(entry.entry_id)
    issue = issue_registry.async_get_issue(DOMAIN, f"plain_password_{entry.entry_id}")
    assert issue is not None
    assert issue.severity is ir.IssueSeverity.WARNING
    assert issue.translation_key == "plain_password"
    await unload_all(hass)
    for options in ({"auth": "digest"}, {"auth": "basic", "tls": "verify"}):
        tls = options.pop("tls", "none")
        data = {**entry.data, "tls": tls, "vendor_options": options}
        hass.config_entries.async_update_entry(entry, data=data)
        async_check_tls(hass, entry)
        assert issue_registry.async_get_issue(DOMAIN, f"plain_password_{entry.entry_id}") is None
    await unload_all(hass)
