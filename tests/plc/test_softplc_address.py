"""SoftPLC addresses, types, values and the read plan, without sockets."""

from __future__ import annotations

import pytest

from custom_components.plc_bridge.plc import PlcAddressError, PlcValueError, Point
from custom_components.plc_bridge.plc.vendors.softplc import SoftplcClient
from custom_components.plc_bridge.plc.vendors.softplc.address import parse_address, reply_key
from custom_components.plc_bridge.plc.vendors.softplc.codec import decode, parse_token
from custom_components.plc_bridge.plc.vendors.softplc.document import Item, request_body
from custom_components.plc_bridge.plc.vendors.softplc.planner import (
    MAX_GAP_WORDS,
    item_of,
    place,
    plan,
)


@pytest.mark.parametrize(
    ("text", "normal", "kind"),
    [
        ("N7:3", "N7:3", "INT"),
        ("n7:3", "N7:3", "INT"),
        ("N7", "N7:0", "INT"),
        ("N7:3/4", "N7:3/4", "BOOL"),
        ("B3/37", "B3:2/5", "BOOL"),
        ("F8:2", "F8:2", "REAL"),
        ("T4:0.PRE", "T4:0.PRE", "INT"),
        ("T4:0.1", "T4:0.PRE", "INT"),
        ("T4:0.DN", "T4:0.DN", "BOOL"),
        ("C5:1.ACC", "C5:1.ACC", "INT"),
        ("R6:0.POS", "R6:0.POS", "INT"),
        ("O:0", "O0:0", "INT"),  # a reply's form is sent in the request form
        ("O0:3", "O0:3", "INT"),
        ("I1:3", "I1:3", "INT"),  # never rewritten into the reply's I:3
        ("I1", "I1", "INT"),  # the manual's request form, sent as typed
        ("i1/2", "I1/2", "BOOL"),
        ("S:5/2", "S2:5/2", "BOOL"),
        ("PD12:3000.SP", "PD12:3000.SP", "REAL"),
        ("timer1", "timer1", "INT"),
    ],
)
def test_addresses(text: str, normal: str, kind: str) -> None:
    """Every form of the manual parses to the manual's spelling and a fitting type."""
    assert SoftplcClient.validate_point(Point(text, "")) == Point(normal, kind)


@pytest.mark.parametrize(
    "text",
    [
        *("N:3", "N10000:0", "N7:3/16", "F8:0/1", "N7:0.PRE", "T4:0.XX", "PD12:1", "I2:0"),
        *("7N", "", "I1.PRE", "I1/16"),
    ],
)
def test_bad_addresses(text: str) -> None:
    """Addresses the datatable cannot have are refused with a message."""
    with pytest.raises(PlcAddressError):
        SoftplcClient.validate_point(Point(text, ""))


@pytest.mark.parametrize(
    ("address", "data_type"),
    [("N7:0", "REAL"), ("F8:0", "INT"), ("N7:0", "BOOL"), ("B3:0/1", "INT"), ("N7:0", "DINT")],
)
def test_type_must_fit(address: str, data_type: str) -> None:
    """A type the address cannot hold is refused."""
    with pytest.raises(PlcAddressError):
        SoftplcClient.validate_point(Point(address, data_type))


def test_normalised_replies_name_the_same() -> None:
    """N0007:0033 and N7:33 are one place, I:0001 and I1:1 too; tags and I1 name none."""
    assert reply_key("N0007:0033") == reply_key("N7:33") == ("N", 7, 33, "")
    assert reply_key("O:0000") == reply_key("O0:0") == ("O", 0, 0, "")
    assert reply_key("I:0001") == reply_key("I1:1") == ("I", 1, 1, "")
    assert reply_key("T0004:0000.PRE") == reply_key("T4:0.PRE")
    assert reply_key("Timer1") is None
    assert reply_key("I1") is None
    assert reply_key("<junk>") is None


def test_opaque_write_of_a_bit_refused() -> None:
    """I1/2's word is the PLC's reading: a bit written back might land in another word."""
    with pytest.raises(PlcAddressError, match="I1:<element>/2"):
        SoftplcClient.validate_value(Point("I1/2", "BOOL"), True)
    assert SoftplcClient.validate_value(Point("O3", "INT"), 5) == 5


@pytest.mark.parametrize(
    ("kind", "value", "checked"),
    [
        ("INT", "0x00FF", 255),
        ("INT", -5, -5),
        ("UINT", "0xF73D", 63293),
        ("WORD", "42", 42),
        ("REAL", "1.5", 1.5),
        ("BOOL", "on", True),
    ],
)
def test_values_decimal_and_hex(kind: str, value: object, checked: object) -> None:
    """Writes take decimal and hex (the manual's two formats), checked before sending."""
    address = {"REAL": "F8:0", "BOOL": "B3:0/1"}.get(kind, "N7:0")
    assert SoftplcClient.validate_value(Point(address, kind), value) == checked  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("kind", "value"), [("INT", 40000), ("UINT", -1), ("INT", "0x1FFFF"), ("REAL", "x")]
)
def test_values_out_of_range(kind: str, value: object) -> None:
    """A value the word cannot hold is refused before anything is sent."""
    address = "F8:0" if kind == "REAL" else "N7:0"
    with pytest.raises(PlcValueError):
        SoftplcClient.validate_value(Point(address, kind), value)  # type: ignore[arg-type]


def test_status_word_not_writable() -> None:
    """A timer's status bits have no word name to PUT: refused before sending."""
    with pytest.raises(PlcAddressError):
        SoftplcClient.validate_value(Point("T4:0.DN", "BOOL"), True)


def test_replies_decoded_in_both_formats() -> None:
    """Replies print words in hex (O, I) or decimal, unsigned (63293 is -2243 as an INT)."""
    assert decode("INT", parse_token("63293", "x"), None, "x") == -2243
    assert decode("UINT", parse_token("0xf73d", "x"), None, "x") == 63293
    assert decode("BOOL", parse_token("0x0020", "x"), 5, "x") is True
    assert decode("REAL", parse_token("21.299999", "x"), None, "x") == 21.3


def test_plan_merges_nearby_elements() -> None:
    """Nearby elements of one file share a range; far ones, other files and tags do not."""
    addresses = [
        parse_address(text)
        for text in (
            *("N7:3", "N7:5", "N7:3/2", f"N7:{6 + MAX_GAP_WORDS}", "N7:200", "T4:0.PRE"),
            *("T4:2.DN", "F8:0", "timer1", "PD9:0.SP", "PD9:0.SP"),
        )
    ]
    items = plan(addresses)
    assert [(item.ad, item.count) for item in items] == [
        ("F8:0", 1),
        ("N7:3", 20),
        ("N7:200", 1),
        ("T4:0", 3),
        ("timer1", 1),
        ("PD9:0.SP", None),
    ]
    cased = plan([parse_address("pump"), parse_address("Pump"), parse_address("pump")])
    assert [item.ad for item in cased] == ["pump", "Pump"]
    assert item_of(parse_address("N7:5"), items) == items[1]


def test_gap_measured_in_words() -> None:
    """Timers have 3 words: a gap of 6 elements is 18 words, beyond MAX_GAP_WORDS."""
    items = plan([parse_address("T4:0"), parse_address("T4:7")])
    assert len(items) == 2


def test_place_by_name_or_elimination() -> None:
    """Replies are placed by what they name (normalised or not), whatever their order; one
    tag left over takes the one reply item left over (a tag answered as its address)."""
    items = plan([parse_address(text) for text in ("N7:33", "O:0", "timer1")])
    assert [item.ad for item in items] == ["N7:33", "O0:0", "timer1"]
    reply = [
        Item("O:0000", 1, ("0x0001",)),
        Item("N0007:0033", 1, ("5",)),
        Item("T0004:0000", 1, ("0", "1", "2")),
    ]
    placed, ambiguous = place(items, reply)
    assert placed[items[0]].tokens == ("5",)
    assert placed[items[1]].tokens == ("0x0001",)
    assert placed[items[2]].ad == "T0004:0000"
    assert not ambiguous


def test_place_never_guesses() -> None:
    """Two tags answered with their addresses, or I1 beside I1:0 answered normalised (I1 may
    be I1:0), cannot be told apart: those items are left unplaced, the others placed."""
    tags = plan([parse_address(text) for text in ("N7:0", "pump", "Pump")])
    reply = [Item("N7:20", 1, ("1",)), Item("N7:0", 1, ("0",)), Item("N7:21", 1, ("2",))]
    placed, _ambiguous = place(tags, reply)
    assert list(placed) == [tags[0]]
    opaque = plan([parse_address(text) for text in ("I1:0", "I1:1", "I1", "F8:0")])
    reply = [
        Item("I:0000", 2, ("1", "2")),
        Item("I:0000", 1, ("2",)),
        Item("F0008:0000", 1, ("1.5",)),
    ]
    placed, ambiguous = place(opaque, reply)
    assert list(placed) == [opaque[0]]  # F8:0 (items are sorted: F8, I1, then I1 alone)
    assert ambiguous == {opaque[1], opaque[2]}


def test_place_by_the_one_answer_left() -> None:
    """I1 beside I1:0 answered I:0001 and I:0000: the range can only be I:0000."""
    items = plan([parse_address(text) for text in ("I1:0", "I1")])
    reply = [Item("I:0001", 1, ("7",)), Item("I:0000", 1, ("5",))]
    placed, ambiguous = place(items, reply)
    assert placed[items[0]].tokens == ("5",)
    assert placed[items[1]].tokens == ("7",)
    assert not ambiguous


def test_place_tags_by_exact_name_first() -> None:
    """pump and Pump echoed are placed by their exact names; spelled as the PLC's table
    (PUMP for both: one tag to a case-blind PLC), each takes one of the equal answers."""
    items = plan([parse_address("pump"), parse_address("Pump")])
    placed, _ = place(items, [Item("Pump", 1, ("2",)), Item("pump", 1, ("1",))])
    assert [placed[item].tokens for item in items] == [("1",), ("2",)]
    placed, _ = place(items, [Item("PUMP", 1, ("3",)), Item("PUMP", 1, ("3",))])
    assert [placed[item].tokens for item in items] == [("3",), ("3",)]
    placed, ambiguous = place(items, [Item("PUMP", 1, ("3",)), Item("PUMP", 1, ("4",))])
    assert not placed
    assert ambiguous == set(items)


def test_request_body() -> None:
    """Reads carry ad and count; writes their values; the XML is escaped by lxml."""
    body = request_body([("N7:0", 2, "42 0xF73D"), ("T4:0.PRE", None, "4000"), ("a&b", 1, None)])
    assert b'<data ad="N7:0" count="2">42 0xF73D</data>' in body
    assert b'<data ad="T4:0.PRE">4000</data>' in body
    assert b'ad="a&amp;b"' in body
