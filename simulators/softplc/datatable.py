"""The simulated SoftPLC datatable: files of words, addresses as the runtime reads them.

Written from the manual alone, not from the client: O, I and S are files 0, 1 and 2; the
digits after them without a colon are the element ("I1" is I:1) or, with `short="file"`, the
file ("I1" is I1:0, as "N7" is N7:0); T, C and R elements have 3 words; a PD element has named
float words.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import re

FIXED = {"O": 0, "I": 1, "S": 2}
WIDE = {"T": 3, "C": 3, "R": 3}
WORD_NAMES = {
    "T": {"PRE": 1, "ACC": 2},
    "C": {"PRE": 1, "ACC": 2},
    "R": {"LEN": 1, "POS": 2},
}
PID_WORDS = ("SP", "PV", "KP", "KI", "KD", "OUT")
_AD = re.compile(r"(PD|[OISBTCRNF])([0-9]*)(?::([0-9]+))?(?:\.([A-Z]+))?")


class Bad(Exception):
    """An item the runtime cannot serve; the text is what the simulator says about it."""


@dataclass
class File:
    """One datatable file: its type and its words (floats for F), or PID elements."""

    type: str
    number: int
    words: list[int | float] = field(default_factory=list)
    pids: list[dict[str, float]] = field(default_factory=list)

    @property
    def width(self) -> int:
        """Words per element."""
        return WIDE.get(self.type, 1)

    @property
    def elements(self) -> int:
        """How many elements the file has."""
        return len(self.pids) if self.type == "PD" else len(self.words) // self.width


@dataclass(frozen=True)
class Target:
    """Where an item's ad points: a file, an element, and a word of it (or a PID word name)."""

    file: File
    element: int
    word: int | None = None  # a word address (T4:0.PRE): one value
    pid: str = ""


def default_files(bench: int = 0) -> dict[tuple[str, int], File]:
    """Return the demo program's datatable; `bench` adds files N10, F11, B12, T13 of that size."""
    files = [
        File("O", 0, [0] * 8),
        File("I", 1, [0x0005, 0, 0, 0, 0, 0, 0, 0]),
        File("S", 2, [0] * 32),
        File("B", 3, [0b1010, 0, 0, 0] + [0] * 12),
        File("T", 4, [0, 4000, 1200] + [0, 1000, 0] * 7),
        File("C", 5, [0, 10, 3] * 4),
        File("R", 6, [0, 16, 0] * 4),
        File("N", 7, list(range(100))),
        File("F", 8, [21.5, 22.0, 0.5] + [0.0] * 17),
        File("PD", 9, pids=[dict.fromkeys(PID_WORDS, 0.0) | {"SP": 50.0, "KP": 1.5}] * 1),
    ]
    files[9].pids = [dict.fromkeys(PID_WORDS, 0.0) | {"SP": 50.0, "KP": 1.5} for _ in range(2)]
    if bench:
        files += [
            File("N", 10, [i % 30000 for i in range(bench)]),
            File("F", 11, [i / 4 for i in range(bench)]),
            File("B", 12, [i & 0xFFFF for i in range(bench)]),
            File("T", 13, [0, 100, 7] * bench),
        ]
    return {(f.type, f.number): f for f in files}


def resolve(files: dict[tuple[str, int], File], ad: str, short: str = "element") -> Target:
    """Return what an ad names; raise Bad (unknown file, element past the end, bad syntax)."""
    match = _AD.fullmatch(ad.strip().upper())
    if match is None:
        raise Bad(f"invalid datatable address '{ad}'")
    type_, digits, element, word = match.groups()
    if type_ in FIXED:
        if element is None and short == "element":
            element, digits = digits or "0", ""
        number = FIXED[type_] if not digits else int(digits)
    elif not digits:
        raise Bad(f"invalid datatable address '{ad}'")
    else:
        number = int(digits)
    file = files.get((type_, number))
    if file is None:
        raise Bad(f"datatable file {type_}{number} does not exist")
    index = int(element or 0)
    if index >= file.elements:
        raise Bad(f"element {index} is beyond the end of {type_}{number}")
    if word is None:
        if type_ == "PD":
            raise Bad("PID elements are addressed by word")
        return Target(file, index)
    if type_ == "PD" and word in PID_WORDS:
        return Target(file, index, pid=word)
    if word in WORD_NAMES.get(type_, {}):
        return Target(file, index, WORD_NAMES[type_][word])
    raise Bad(f"invalid word '{word}' in '{ad}'")


def normalised(target: Target, fixed: str = "short") -> str:
    """Return the runtime's normalised spelling: N0007:0033, O:0000 (or O0000:0000), T...PRE."""
    file = target.file
    short = file.type in FIXED and fixed == "short"
    head = file.type if short else f"{file.type}{file.number:04d}"
    text = f"{head}:{target.element:04d}"
    if target.pid:
        return f"{text}.{target.pid}"
    if target.word is not None:
        name = next(k for k, v in WORD_NAMES[file.type].items() if v == target.word)
        return f"{text}.{name}"
    return text
