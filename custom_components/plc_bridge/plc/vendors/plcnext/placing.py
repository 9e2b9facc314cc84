"""PLCnext answers: values placed under their paths, unknown names found by halving.

Pure decisions about answers, tested through the reader: no request is made here.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Awaitable, Callable, Sequence
from dataclasses import dataclass, field
from operator import itemgetter
from typing import Any

from ...errors import PlcAddressError, PlcError, PlcProtocolError
from .errors import ApiError, reasons_of
from .paths import VariablePath, folded, same_path


@dataclass(slots=True)
class Reading:
    """Raw values and per-path errors, by path key, and the projectCRC the answer carried."""

    found: dict[str, Any] = field(default_factory=dict)
    failed: dict[str, PlcError] = field(default_factory=dict)
    crc: Any = None


def place(
    answer: Any,
    paths: Sequence[VariablePath],
    reading: Reading,
    names: list[str] | None = None,
) -> None:
    """Put an answer's variables under their paths: by position where every path agrees.

    The PLC answers in request order; an entry whose `path` names another variable, or a list
    of another length, is matched by path instead, so that no value shows under a wrong point.
    `names`: the paths as a group was registered (what its answers name them).
    """
    entries = answer.get("variables") if isinstance(answer, dict) else None
    if not isinstance(entries, list):
        raise PlcProtocolError("the PLC's answer holds no variables")
    reading.crc = answer.get("projectCRC")
    if len(entries) == len(paths):
        if names is not None and as_registered(entries, paths, names, reading):
            return
        if in_order(entries, paths, reading):
            return
    for path, entry in zip(paths, by_path(entries, paths), strict=True):
        if entry is not None and "value" in entry and entry.get("error") is None:
            reading.found[path.key] = entry["value"]
        else:
            reading.failed[path.key] = failure(entry, path)


def as_registered(
    entries: list[Any], paths: Sequence[VariablePath], names: list[str], reading: Reading
) -> bool:
    """Place the entries by position and return True, if each is named as registered, valued.

    A group's usual answer (entries of `path`, `type`, `value`: Groups page, Read Group),
    checked a list at a time rather than entry by entry.
    """
    try:
        if list(map(itemgetter("path"), entries)) != names:
            return False
        values = list(map(itemgetter("value"), entries))
    except (KeyError, TypeError):  # an entry with no path or value, or no object at all
        return False
    if [entry.get("error") for entry in entries].count(None) != len(entries):
        return False
    reading.found.update(zip([path.key for path in paths], values, strict=True))
    return True


def in_order(entries: list[Any], paths: Sequence[VariablePath], reading: Reading) -> bool:
    """Place the entries by position and return True, if each names its path (or none).

    The PLC answers in request order (Groups page): a relative name counts where no other
    path has it; another case counts (a PLC may answer with the declared spelling).
    """
    found: dict[str, Any] = {}
    failed: dict[str, PlcError] = {}
    relative: list[bool] = []  # computed once, where first needed
    for entry, path in zip(entries, paths, strict=True):
        if type(entry) is not dict:
            return False
        named = entry.get("path", path.text)
        if named != path.text:
            if not relative:
                relative.append(unique_names(paths))
            if not relative[0] or (named != path.name and not same_path(named, path)):
                return False
        if "value" in entry and entry.get("error") is None:
            found[path.key] = entry["value"]
        else:
            failed[path.key] = failure(entry, path)
    reading.found.update(found)
    reading.failed.update(failed)
    return True


def unique_names(paths: Sequence[VariablePath]) -> bool:
    """True when no two paths share their name in their component (in any case)."""
    if len({path.component for path in paths}) == 1:
        return True
    return len({folded(path.name) for path in paths}) == len(paths)


def failure(entry: dict[str, Any] | None, path: VariablePath) -> PlcError:
    """Return the error of an entry that holds no value (or of a path with no entry)."""
    if entry is None:
        return PlcProtocolError(f"{path.text} is missing from the answer")
    if entry.get("error") is not None:
        said = ", ".join(reasons_of(entry["error"])) or "no reason given"
        return PlcAddressError(f"{path.text}: the PLC says {said}")
    return PlcProtocolError(f"{path.text}: the answer has no value")


def by_path(entries: list[Any], paths: Sequence[VariablePath]) -> list[Any]:
    """Return each path's entry, None where none or several could be it.

    Named as sent (in full, or relative where no other path has that name), else the only
    entry left that names it in another case (where no other path differs in case alone).
    """
    named: dict[str, list[Any]] = {}
    for entry in entries:
        name = entry.get("path") if isinstance(entry, dict) else None
        if isinstance(name, str):
            named.setdefault(name.strip(), []).append(entry)
    relative = Counter(path.name for path in paths)
    chosen: list[Any] = []
    for path in paths:
        found = named.get(path.text, [])
        if relative[path.name] == 1:
            found = found + named.get(path.name, [])
        chosen.append(found[0] if len(found) == 1 else None)
    if all(entry is not None for entry in chosen):
        return chosen
    taken = {id(entry) for entry in chosen if entry is not None}
    by_fold: dict[str, list[Any]] = {}
    for name, listed in named.items():
        by_fold.setdefault(folded(name), []).extend(listed)
    spelled = Counter(folded(path.name) for path in paths)
    for index, path in enumerate(paths):
        if chosen[index] is not None or spelled[folded(path.name)] > 1:
            continue
        keys = [folded(path.text)] + ([folded(path.name)] if relative[path.name] == 1 else [])
        found = [e for key in keys for e in by_fold.get(key, []) if id(e) not in taken]
        if len(found) == 1:
            chosen[index] = found[0]
            taken.add(id(found[0]))
    return chosen


async def isolate(
    paths: Sequence[VariablePath],
    attempt: Callable[[Sequence[VariablePath]], Awaitable[Any]],
    unknown: dict[str, PlcError],
) -> tuple[list[VariablePath], Any]:
    """Try the paths; on 404 find the unknown names one at a time, each by halving.

    A 404 names no path (PyREST's log: `invalidNames`), so the rest is tried as a whole and,
    refused, halved down to its first unknown name: about log2(N) + 2 requests a name. Return
    the paths the PLC knows and the answer of an attempt that took them all (None if none did).
    """
    known: list[VariablePath] = []
    rest = list(paths)
    while rest:
        try:
            answer = await attempt(rest)
        except ApiError as err:
            if err.status != 404:
                raise
            words = err.words
        else:
            return known + rest, None if known else answer
        low, high = 0, len(rest)  # rest[low:high] holds an unknown name; rest[:low] does not
        while high - low > 1:
            middle = (low + high) // 2
            try:
                await attempt(rest[low:middle])
            except ApiError as err:
                if err.status != 404:
                    raise
                high, words = middle, err.words
            else:
                low = middle
        unknown[rest[low].key] = PlcAddressError(
            f"{rest[low].text}: the PLC does not know this variable, or it has no HMI flag "
            f"({words})"
        )
        known += rest[:low]
        rest = rest[low + 1 :]
    return known, None
