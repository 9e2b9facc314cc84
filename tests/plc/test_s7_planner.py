"""The S7 read/write planner: pure functions, no sockets."""

from __future__ import annotations

import random

import pytest

from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors.s7 import S7Client
from custom_components.plc_bridge.plc.vendors.s7.address import (
    AREA_C,
    AREA_DB,
    AREA_I,
    AREA_M,
    AREA_P,
    AREA_T,
)
from custom_components.plc_bridge.plc.vendors.s7.planner import (
    MAX_ITEMS,
    PARAMETER,
    REPLY_HEADER,
    REQUEST_HEADER,
    SPEC,
    Span,
    WriteItem,
    assemble,
    extract,
    failed_needs,
    locate,
    max_data,
    merge,
    pack,
    plan_reads,
    plan_writes,
    split,
    write_pieces,
)


def db(number: int, start: int, length: int) -> Span:
    return Span(AREA_DB, number, start, length)


def poll_of_100() -> list[Point]:
    """A typical HMI poll: bits, words and reals in four DBs, M, I and Q."""
    points = [Point(f"DB1.DBX0.{bit}", "BOOL") for bit in range(8)]
    points += [Point(f"DB1.DBW{2 + 2 * i}", "INT") for i in range(15)]
    points += [Point(f"DB1.DBD{40 + 4 * i}", "REAL") for i in range(12)]
    points += [Point(f"DB2.DBD{4 * i}", "REAL") for i in range(20)]
    points += [Point(f"DB3.DBW{20 * i}", "INT") for i in range(10)]
    points += [Point(f"M{i // 8}.{i % 8}", "BOOL") for i in range(10)]
    points += [Point(f"MW{10 + 2 * i}", "WORD") for i in range(5)]
    points += [Point(f"IW{64 + 2 * i}", "WORD") for i in range(4)]
    points += [Point(f"I0.{bit}", "BOOL") for bit in range(8)]
    points += [Point(f"Q0.{bit}", "BOOL") for bit in range(4)]
    points += [Point(f"DB4.DBD{100 * i}", "DINT") for i in range(4)]
    assert len(points) == 100
    return points


def check_budgets(plan: list[list[Span]], pdu: int, max_items: int = MAX_ITEMS) -> None:
    """Every request and its reply fit the PDU, and no request has too many items."""
    for request in plan:
        assert 1 <= len(request) <= max_items
        assert REQUEST_HEADER + PARAMETER + SPEC * len(request) <= pdu
        assert REPLY_HEADER + PARAMETER + sum(span.reply_cost for span in request) <= pdu


def test_merge_neighbours() -> None:
    needs = [db(1, 0, 2), db(1, 2, 2), db(1, 3, 4), db(1, 12, 1), db(1, 30, 2), db(2, 0, 1)]
    assert merge(needs) == [db(1, 0, 13), db(1, 30, 2), db(2, 0, 1)]
    assert merge(needs, max_gap=0) == [db(1, 0, 7), db(1, 12, 1), db(1, 30, 2), db(2, 0, 1)]
    assert merge(needs, max_gap=100) == [db(1, 0, 32), db(2, 0, 1)]
    assert merge([db(1, 4, 2), db(1, 0, 2), db(1, 4, 2)]) == [db(1, 0, 6)]  # sorted, deduped


def test_merge_keeps_alone_apart() -> None:
    bad = db(1, 2, 2)
    assert merge([db(1, 0, 2), bad, db(1, 4, 2)], alone={bad}) == [db(1, 0, 2), bad, db(1, 4, 2)]


def test_merge_periphery_only_touching() -> None:
    needs = [Span(AREA_P, 0, 256, 2), Span(AREA_P, 0, 258, 2), Span(AREA_P, 0, 262, 2)]
    assert merge(needs) == [Span(AREA_P, 0, 256, 4), Span(AREA_P, 0, 262, 2)]


def test_merge_timers_by_bytes() -> None:
    timers = [Span(AREA_T, 0, 0, 1), Span(AREA_T, 0, 4, 1), Span(AREA_T, 0, 10, 1)]
    assert merge(timers) == [Span(AREA_T, 0, 0, 5), Span(AREA_T, 0, 10, 1)]  # gap 3 = 6 bytes
    assert Span(AREA_C, 0, 0, 5).size == 10


def test_split() -> None:
    assert split(db(1, 0, 1000), 462) == [db(1, 0, 462), db(1, 462, 462), db(1, 924, 76)]
    assert split(db(1, 0, 10), 462) == [db(1, 0, 10)]
    assert split(Span(AREA_T, 0, 0, 300), 462) == [
        Span(AREA_T, 0, 0, 231),
        Span(AREA_T, 0, 231, 69),
    ]
    with pytest.raises(ValueError, match="cannot carry one item"):
        split(Span(AREA_T, 0, 0, 3), 1)


def test_pack_item_cap() -> None:
    spans = [db(n, 0, 1) for n in range(1, 26)]
    assert [len(request) for request in pack(spans, 480)] == [25]  # no cap but the PDU's
    plan = pack(spans, 480, max_items=20)  # a CPU that showed it takes 20
    assert [len(request) for request in plan] == [20, 5]
    check_budgets(plan, 480, 20)
    assert [len(request) for request in pack([db(n, 0, 1) for n in range(1, 100)], 960)] == [
        79,
        20,
    ]  # at PDU 960 the request's address specs bind: 12 + 79 * 12 <= 960


def test_pack_reply_budget() -> None:
    plan = pack([db(1, 0, 200), db(2, 0, 200), db(3, 0, 200), db(4, 0, 30)], 480)
    assert [len(request) for request in plan] == [3, 1]  # 204+204+34 bytes, then 204
    check_budgets(plan, 480)


def test_pack_request_budget_on_a_small_pdu() -> None:
    plan = pack([db(n, 0, 1) for n in range(1, 21)], 240)
    assert [len(request) for request in plan] == [19, 1]  # a job header is 10 bytes: 12 + 19 * 12
    check_budgets(plan, 240)
    words = pack([db(n, 0, 2) for n in range(1, 20)], 240)
    assert words == [sorted(db(n, 0, 2) for n in range(1, 20))]  # reply: 14 + 19 * 6 <= 240
    reals = pack([db(n, 0, 12) for n in range(1, 20)], 240)
    assert [len(request) for request in reals] == [14, 5]  # the reply binds: 14 + 14 * 16 = 238
    check_budgets(reals, 240)


def test_plan_reads_a_poll_of_100_points() -> None:
    assert S7Client.requests_for(poll_of_100()) == 1  # one read (the status: once a minute)
    assert S7Client.requests_for(poll_of_100(), pdu_size=240) == 2
    assert S7Client.requests_for([Point("nonsense", "INT")]) == 0
    assert S7Client.requests_for([]) == 0


def test_plan_reads_picks_the_gap_that_saves_requests() -> None:
    words = [db(1, 15 * i, 2) for i in range(30)]  # 30 words, 13 bytes apart
    assert plan_reads(words, 480) == [words]  # 30 items fit one request: fewer bytes
    plan = plan_reads(words, 480, max_items=20)
    assert plan == [[db(1, 0, 437)]]  # one item across the gaps, not 30 items in two requests
    far = [db(1, 300 * i, 2) for i in range(30)]  # gaps too long: items
    assert len(plan_reads(far, 480, max_items=20)) == 2
    assert len(plan_reads([db(1, 0, 2), db(1, 10, 2)], 480)[0]) == 1


def test_plan_reads_never_exceeds_the_limits() -> None:
    rng = random.Random(7)
    for pdu in (240, 480, 960):
        for _ in range(30):
            areas, lengths = (AREA_DB, AREA_M, AREA_I, AREA_T), (1, 2, 4, 8, 256)
            needs = {
                Span(
                    rng.choice(areas), rng.randint(1, 3), rng.randint(0, 2000), rng.choice(lengths)
                )
                for _ in range(rng.randint(1, 120))
            }
            plan = plan_reads(needs, pdu)
            check_budgets(plan, pdu)
            got = [(span, bytes(span.size)) for request in plan for span in request]
            assert all(assemble(need, got) == bytes(need.size) for need in needs)


def test_assemble() -> None:
    need = db(1, 4, 4)
    merged = (db(1, 0, 10), bytes(range(10)))
    assert assemble(need, [merged]) == bytes([4, 5, 6, 7])
    pieces = [(db(1, 0, 6), bytes(range(6))), (db(1, 6, 4), bytes(range(6, 10)))]
    assert assemble(need, pieces) == bytes([4, 5, 6, 7])
    assert assemble(need, [(db(2, 4, 4), b"xxxx"), (db(1, 0, 6), 0x05)]) == 0x05
    timer = Span(AREA_T, 0, 2, 1)
    assert assemble(timer, [(Span(AREA_T, 0, 0, 3), b"\x00\x01\x00\x02\x00\x03")]) == b"\x00\x03"
    with pytest.raises(ValueError, match="no item read covers"):
        assemble(need, [(db(1, 0, 6), bytes(6))])


def test_overlapping_items() -> None:
    wide, narrow, tail = db(1, 0, 10), db(1, 8, 1), db(1, 12, 2)
    got: list[tuple[Span, bytes | int]] = [(wide, 0x05), (narrow, b"\x07"), (tail, b"\x01\x02")]
    assert extract([narrow, db(1, 12, 1), wide], got) == {
        narrow: b"\x07",  # read by its own item, whatever the wide one's fate
        db(1, 12, 1): b"\x01",
        wide: 0x05,
    }
    assert locate([db(1, 9, 1), db(2, 0, 1)], [wide, narrow, tail]) == {
        db(1, 9, 1): [0],
        db(2, 0, 1): [],
    }


def test_failed_needs() -> None:
    a, b, c = db(1, 0, 2), db(1, 2, 2), db(2, 0, 2)
    got: list[tuple[Span, bytes | int]] = [(db(1, 0, 4), 0x05), (c, 0x0A)]
    assert failed_needs([a, b, c], got) == {a, b}  # c failed alone: its own error
    assert failed_needs([a, b, c], [(db(1, 0, 4), b"1234"), (c, b"12")]) == set()
    where = locate([a, b, c], [span for span, _ in got])
    assert failed_needs([a, b, c], got, where) == {a, b}  # the poll's located plan: linear


def test_failed_needs_at_10000() -> None:
    """5,000 failed items of two needs each: found through the plan's locations, not by
    comparing every need with every item (25 million comparisons took 9 s)."""
    needs = [db(1, 4 * i + half, 2) for i in range(5000) for half in (0, 2)]
    got: list[tuple[Span, bytes | int]] = [(db(1, 4 * i, 4), 0x05) for i in range(5000)]
    calls = 0
    real_overlaps = Span.overlaps

    def counted(self: Span, other: Span) -> bool:
        nonlocal calls
        calls += 1
        return real_overlaps(self, other)

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(Span, "overlaps", counted)
        assert failed_needs(needs, got) == set(needs)
    assert calls < 50_000


def test_plan_writes() -> None:
    items = [WriteItem(db(n, 0, 1), b"\x01", 0) for n in range(1, 31)]
    assert [len(request) for request in plan_writes(items, 480)] == [26, 4]  # 12 + 26 * 18 <= 480
    plan = plan_writes(items, 480, max_items=20)
    assert [len(request) for request in plan] == [20, 10]
    assert [item for request in plan for item in request] == items  # order kept
    big = [WriteItem(db(1, 0, 300), bytes(300)), WriteItem(db(1, 300, 300), bytes(300))]
    assert [len(request) for request in plan_writes(big, 480)] == [1, 1]
    assert plan_writes([], 480) == []


def test_write_pieces() -> None:
    pieces = write_pieces(db(1, 10, 256), bytes(range(256)), 240)
    assert [piece.span for piece in pieces] == [db(1, 10, 212), db(1, 222, 44)]  # 10+2+16+212
    assert b"".join(piece.data for piece in pieces) == bytes(range(256))
    assert write_pieces(Span(AREA_C, 0, 3, 1), b"\x00\x07", 240) == [
        WriteItem(Span(AREA_C, 0, 3, 1), b"\x00\x07")
    ]
    assert max_data(240) == 222
