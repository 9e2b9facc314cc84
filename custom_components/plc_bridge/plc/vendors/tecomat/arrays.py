"""TecoApi answers: the arrays a poll reads whole (5.2), and where an answer places each path.

The spec shows arrays only whole, as nested JSON arrays (5.2: `arr2` answers `[[0.0, ...], ...]`),
and no answer to some of an array's elements. So a poll that needs several elements of one array,
or an element of a multi-dimensional one, reads the array whole and indexes it. A JSON array
says nothing of the first index, which IEC 61131-3 lets a program choose (`ARRAY[1..5]`; 5.2 asks
for 0): it is indexed by position only once the PLC has confirmed the first and last elements
as [0, ..] and [n - 1, ..] (`corners`); otherwise its elements are asked by their own index, as
for an array too big for one answer (413.004). An answer to elements places a value only where
its shape names the index, or by position from a first index the PLC confirmed or declared
(simulators/tecomat/READINGS.md, rows 1 and 18).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from ...errors import PlcAddressError
from .paths import VariablePath
from .reading import Reading, gone_for

_MISSING = object()
type Walk = list[tuple[VariablePath, int]]  # paths with the number of segments already followed
type Lows = Mapping[str, tuple[int, ...]]  # each array's first index of every dimension, by key
type Lists = dict[str, tuple[VariablePath, tuple[int, ...]]]  # unplaced lists: array, lengths


def array_of(path: VariablePath) -> VariablePath | None:
    """Return the array a path indexes: its segments before the first index; None without one."""
    return VariablePath(path.segments[: path.first_index]) if path.first_index else None


@dataclass(slots=True)
class ArrayPlan:
    """What a read asks: paths as they are, and the arrays read whole with the paths inside."""

    asked: dict[str, VariablePath] = field(default_factory=dict)
    inside: dict[str, list[VariablePath]] = field(default_factory=dict)  # by the array's key


def array_plan(paths: dict[str, VariablePath], by_elements: set[str]) -> ArrayPlan:
    """Return what to ask: an array holding two asked paths, or one path of several indices, whole.

    An array whose elements are asked instead (`by_elements`: too big, or its first index not
    confirmed as 0) has its paths asked as they are.
    """
    if not any(path.first_index for path in paths.values()):
        return ArrayPlan(paths)
    arrays: dict[str, tuple[VariablePath, list[VariablePath]]] = {}
    result = ArrayPlan()
    for key, path in paths.items():
        array = array_of(path)
        if array is None or array.key in by_elements:
            result.asked[key] = path
        else:
            arrays.setdefault(array.key, (array, []))[1].append(path)
    for key, (array, inside) in arrays.items():
        several = sum(1 for part in inside[0].segments if isinstance(part, int)) > 1
        if len(inside) > 1 or several:
            result.asked[key] = array
            result.inside[key] = inside
        else:
            result.asked[inside[0].key] = inside[0]
    return result


@dataclass(slots=True)
class Placed:
    """What placing the arrays read whole left: paths to ask alone, arrays to confirm first."""

    later: dict[str, VariablePath] = field(default_factory=dict)
    unconfirmed: dict[str, tuple[VariablePath, VariablePath]] = field(default_factory=dict)


def place_arrays(plan: ArrayPlan, reading: Reading, by_elements: set[str], lows: Lows) -> Placed:
    """Index the arrays read whole into the reading where their indices are sure.

    Sure: an answer keyed by index, or a JSON array whose first indices are known (`lows`). Any
    other JSON array is returned with its corners to confirm; one too big or of no shape to
    confirm joins `by_elements` and has its paths returned to be asked alone.
    """
    placed = Placed()
    for key, inside in plan.inside.items():
        array = plan.asked[key]
        if key in reading.too_big:
            elements_later(key, inside, by_elements, placed)
        elif key in reading.found:
            raw = reading.found[key]
            if isinstance(raw, dict) or key in lows:
                place_whole(plan, key, reading, lows)
            elif (ends := corners(raw, array, inside)) is not None:
                placed.unconfirmed[key] = ends
            else:
                elements_later(key, inside, by_elements, placed)
        else:
            for path in inside:
                gone = gone_for(path, reading.gone)
                reading.failed[path.key] = gone.error(path) if gone else reading.failed[key]
    return placed


def elements_later(
    key: str, inside: list[VariablePath], by_elements: set[str], placed: Placed
) -> None:
    """Ask an array's paths by their own index, from now on (until the program changes)."""
    by_elements.add(key)
    placed.later.update((path.key, path) for path in inside)


def place_whole(plan: ArrayPlan, key: str, reading: Reading, lows: Lows) -> None:
    """Index one array read whole into the reading; an index it lacks fails that path alone."""
    array, inside = plan.asked[key], plan.inside[key]
    found = elements(reading.found[key], array, inside, lows)
    reading.found.update(found)
    for path in inside:
        if path.key not in found:
            reading.failed[path.key] = PlcAddressError(  # as 400.005 for it alone
                f"{path.text}: the array {array.text} has no such element"
            )


def corners(
    raw: Any, array: VariablePath, inside: Sequence[VariablePath]
) -> tuple[VariablePath, VariablePath] | None:
    """Return the first and last elements a JSON array holds if it starts at 0, in each dimension.

    When the PLC knows both, every dimension starts at 0 (n elements from 0 to n - 1). None when
    the answer is not nested deep enough for the asked indices.
    """
    depth = max(_depth(path, len(array.segments)) for path in inside)
    lengths: list[int] = []
    node = raw
    for _ in range(depth):
        if not isinstance(node, list) or not node:
            return None
        lengths.append(len(node))
        node = node[0]
    first = VariablePath((*array.segments, *(0 for _ in lengths)))
    last = VariablePath((*array.segments, *(length - 1 for length in lengths)))
    return first, last


def known(reading: Reading, ends: Sequence[VariablePath]) -> bool:
    """True when the PLC refused none of the paths as unknown (400.005): it has them all.

    Whatever shape their values came in: the proof needs their names only.
    """
    return all(gone_for(end, reading.gone) is None for end in ends)


def _depth(path: VariablePath, start: int) -> int:
    """Return how many indices follow one another from `start` in a path."""
    end = start
    while end < len(path.segments) and isinstance(path.segments[end], int):
        end += 1
    return end - start


def answered(
    answer: Any, paths: Sequence[VariablePath], lows: Lows | None = None, lists: Lists | None = None
) -> dict[str, Any]:
    """Return each path's value in a GetObject answer, by key; a path it cannot place is absent.

    Members nest as in 5.1; an element may come keyed in its parent ("arr2[1][3]", "arr2[1,3]"),
    under index keys ({"arr2": {"1": {"3": ...}}}) or in a nested array. A JSON array holds the
    asked elements only when it has exactly as many items as indices were asked at that level:
    then in index order (the client asks elements in index order). A longer one (the whole
    array, or one padded up to the last asked) holds them by position from the array's first
    index: placed only where `lows` knows it (READINGS.md row 18); else it is noted in `lists`
    (the array, its lengths) for the client to confirm, and places nothing.
    """
    found: dict[str, Any] = {}
    rest = [path for path in paths if path.first_index or not _by_exact_names(answer, path, found)]
    if rest:
        places = _Places(found, lows or {}, {} if lists is None else lists)
        _place(answer, [(path, 0) for path in rest], places, whole=False)
    return found


@dataclass(slots=True)
class _Places:
    """Where a walk through an answer records: values found, first indices known, lists unplaced."""

    found: dict[str, Any]
    lows: Lows
    lists: Lists


def _by_exact_names(answer: Any, path: VariablePath, found: dict[str, Any]) -> bool:
    """Place a path of names only where each is a member spelled exactly so; else False.

    What `_by_name` finds first, without its walk: most points of most polls are found so.
    """
    node = answer
    for name in path.segments:
        if type(node) is not dict or (node := node.get(name, _MISSING)) is _MISSING:
            return False
    found[path.key] = node
    return True


def elements(
    array: Any, root: VariablePath, paths: Sequence[VariablePath], lows: Lows
) -> dict[str, Any]:
    """Return the values of paths inside an array read whole; an index it lacks is absent."""
    found: dict[str, Any] = {}
    places = _Places(found, lows, {})
    _place(array, [(path, len(root.segments)) for path in paths], places, whole=True)
    return found


def list_corners(array: VariablePath, lengths: Sequence[int]) -> tuple[VariablePath, VariablePath]:
    """Return the first and last elements of an array from 0 with the given lengths."""
    first = VariablePath((*array.segments, *(0 for _ in lengths)))
    last = VariablePath((*array.segments, *(length - 1 for length in lengths)))
    return first, last


def from_zero(proof: Reading, array: VariablePath, lengths: Sequence[int]) -> bool:
    """True when a probe of a list's corners proves the array starts at 0 in every dimension.

    The corners [0, ..] and [m - 1, ..] of a list answered to some elements must both be known,
    and each answer that holds the last corner must again be a list of the same lengths along
    it: a list holds elements by position from the first index (whole, or padded up to the
    last asked), so one that started below 0 would come longer than m. The names alone do not
    prove it: a padded list of ARRAY[-2..2] asked for [0] is 3 long, and [0] and [2] exist.
    """
    first, last = list_corners(array, lengths)
    if not known(proof, (first, last)):
        return False
    checked = False
    for answer, asked in proof.answers:
        if not any(path.key == last.key for path in asked):
            continue
        node = answered(answer, [array]).get(array.key)
        for length in lengths:
            if not isinstance(node, list) or len(node) != length:
                return False
            node = node[length - 1]
        checked = True
    return checked


def place_again(reading: Reading, lows: Lows) -> None:
    """Place again the paths a reading's answers left unplaced, now that more lows are known."""
    for answer, asked in reading.answers:
        left = [path for path in asked if path.key not in reading.found]
        if left and (found := answered(answer, left, lows)):
            reading.found.update(found)
            for key in found:
                reading.failed.pop(key, None)


def _place(node: Any, walk: Walk, places: _Places, *, whole: bool, order: bool = False) -> None:
    """Follow every path of walk down from node (all at node now), recording where each ends.

    `order`: a list above held only the asked elements (by order, not by position): so must
    every list below it.
    """
    names: Walk = []
    indices: Walk = []
    for path, at in walk:
        if at == len(path.segments):
            places.found[path.key] = node
        elif isinstance(path.segments[at], int):
            indices.append((path, at))
        else:
            names.append((path, at))
    if names and isinstance(node, dict):
        _by_name(node, names, places)
    if indices:
        if isinstance(node, list):
            _by_position(node, indices, places, whole=whole, order=order)
        elif isinstance(node, dict):
            _by_index_key(node, indices, places, whole=whole, order=order)


def _descend(
    hits: list[tuple[Any, VariablePath, int]], places: _Places, whole: bool, order: bool = False
) -> None:
    """Continue each (child, path, at) below its child; siblings below one node go together."""
    groups: dict[int, tuple[Any, Walk]] = {}
    for child, path, at in hits:
        groups.setdefault(id(child), (child, []))[1].append((path, at))
    for child, walk in groups.values():
        _place(child, walk, places, whole=whole, order=order)


def _by_name(node: dict[str, Any], walk: Walk, places: _Places) -> None:
    """Follow a member name, with the indices after it when the answer keys them ("arr1[2]")."""
    folded: dict[str, Any] | None = None
    hits: list[tuple[Any, VariablePath, int]] = []
    for path, at in walk:
        segments = path.segments
        end = at + 1
        while end < len(segments) and isinstance(segments[end], int):
            end += 1
        name = segments[at]
        assert isinstance(name, str)
        for stop in range(end, at, -1):  # "arr2[1][3]" or "arr2[1,3]", then "arr2[1]", "arr2"
            value = _MISSING
            for key in _spellings(name, segments[at + 1 : stop]):
                value = node.get(key, _MISSING)
                if value is _MISSING:
                    if folded is None:
                        folded = {str(k).lower(): v for k, v in node.items()}
                    value = folded.get(key.lower(), _MISSING)
                if value is not _MISSING:
                    break
            if value is _MISSING:
                continue
            if stop == len(segments):  # the common case: a member's own value
                places.found[path.key] = value
            else:
                hits.append((value, path, stop))
            break
    if hits:
        _descend(hits, places, False)  # an array below a member is not one read whole


def _spellings(name: str, indices: tuple[object, ...]) -> tuple[str, ...]:
    """Return how an answer may key a name with indices: arr2[1][3] and arr2[1,3]."""
    if not indices:
        return (name,)
    brackets = name + "".join(f"[{index}]" for index in indices)
    if len(indices) == 1:
        return (brackets,)
    listed = ",".join(str(index) for index in indices)
    return brackets, f"{name}[{listed}]", f"{name}[{listed.replace(',', ', ')}]"


def _by_position(node: list[Any], walk: Walk, places: _Places, *, whole: bool, order: bool) -> None:
    """Follow an index into a JSON array: by order when it holds only the asked, else by position.

    By order when it holds exactly as many items as indices were asked (the asked elements
    only; an answer to elements never holds one the PLC lacks). Else it is the whole array or
    one padded up to the last asked (and always for an array read whole): by position from the
    array's first index in that dimension, only where it is known. Unknown: nothing is placed,
    and a list at the array's first dimension is noted for the client to confirm.
    """
    asked = sorted({_index(path, at) for path, at in walk})
    hits: list[tuple[Any, VariablePath, int]] = []
    if not whole and len(node) == len(asked):
        places_of = {index: position for position, index in enumerate(asked)}
        hits = [(node[places_of[_index(path, at)]], path, at + 1) for path, at in walk]
        low = _low(*walk[0], places.lows)
        # By order and by position agree when the asked run from the first index on: a
        # padded or whole list may go on below; else only lists of the asked elements may.
        start = asked[0] if low is None else low
        order = order or asked != list(range(start, start + len(asked)))
        if low is None and not order:
            _note_list(node, walk, places.lists)  # a list below may need the first index
    elif order:
        return  # longer than asked below a list of the asked elements only: no known shape
    else:
        unknown: Walk = []
        for path, at in walk:
            low = _low(path, at, places.lows)
            if low is None:
                unknown.append((path, at))
            elif 0 <= (position := _index(path, at) - low) < len(node):
                hits.append((node[position], path, at + 1))
        if unknown and not whole:
            _note_list(node, unknown, places.lists)
    _descend(hits, places, whole, order)


def _note_list(node: list[Any], walk: Walk, lists: Lists) -> None:
    """Note a list answered at an array's first dimension: its array and lengths, to confirm."""
    path, at = walk[0]
    start = _run_start(path, at)
    if start != at:
        return  # a row keyed in its parent ("arr2[1]": [...]): its corners are not all known
    depth = max(_depth(other, at) for other, _ in walk)
    lengths: list[int] = []
    level: Any = node
    for _ in range(depth):
        if not isinstance(level, list) or not level:
            return  # too shallow for the asked indices: no corners to probe
        lengths.append(len(level))
        level = next((item for item in level if isinstance(item, list)), None)
    array = VariablePath(path.segments[:start])
    lists.setdefault(array.key, (array, tuple(lengths)))


def _run_start(path: VariablePath, at: int) -> int:
    """Return where the indices that hold `at` start: the array's segments end there."""
    start = at
    while start > 0 and isinstance(path.segments[start - 1], int):
        start -= 1
    return start


def _low(path: VariablePath, at: int, lows: Lows) -> int | None:
    """Return the first index of the dimension `at` indexes, when known."""
    if not lows:
        return None
    start = _run_start(path, at)
    known_lows = lows.get(VariablePath(path.segments[:start]).key)
    dimension = at - start
    return known_lows[dimension] if known_lows and dimension < len(known_lows) else None


def _by_index_key(
    node: dict[str, Any], walk: Walk, places: _Places, *, whole: bool, order: bool
) -> None:
    """Follow an index into an object keyed by indices ({"1": ...})."""
    hits = []
    for path, at in walk:
        value = node.get(str(path.segments[at]), _MISSING)
        if value is not _MISSING:
            hits.append((value, path, at + 1))
    _descend(hits, places, whole, order)


def _index(path: VariablePath, at: int) -> int:
    """Return the index segment of a path."""
    part = path.segments[at]
    assert isinstance(part, int)
    return part
