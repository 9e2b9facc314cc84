"""Pure planning helpers."""

from __future__ import annotations

from custom_components.plc_bridge.plc.planning import chunks, pack


def test_chunks() -> None:
    assert chunks(list(range(5)), 2) == [[0, 1], [2, 3], [4]]
    assert chunks([], 3) == []


def test_pack_by_budget_and_count() -> None:
    words = ["aa", "bbb", "c", "dddd", "ee"]
    assert pack(words, len, 5) == [["aa", "bbb"], ["c", "dddd"], ["ee"]]
    assert pack(words, len, 100, max_items=2) == [["aa", "bbb"], ["c", "dddd"], ["ee"]]
    assert pack(words, len, 6, base=2) == [["aa"], ["bbb", "c"], ["dddd"], ["ee"]]


def test_pack_oversized_item_alone() -> None:
    assert pack(["x" * 10, "y"], len, 5) == [["x" * 10], ["y"]]
    assert pack([], len, 5) == []
