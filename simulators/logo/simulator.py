"""A Siemens LOGO! 0BA7, 0BA8 or 8.x on loopback: the S7 simulator serving a LOGO!'s VM as DB1.

What a LOGO! does differently from an S7 CPU, as public sources describe it (READINGS.md): it
accepts only the server TSAPs of the connections configured in it (no rack/slot), negotiates a
PDU of 240 bytes, answers no SZL list and no clock function, and serves one data block, DB1:
V0..V849 for the program's parameters and, above, the images of its blocks at the offsets of
its generation. Its images are laid out here from the byte ranges the sources give, on their
own, not from the client's tables, so that a slip in either shows in the tests.
"""

from __future__ import annotations

import re
import struct

from simulators.s7 import S7Simulator

# Image of each block kind: first VM byte, bytes (openHAB plclogo's LOGO_MEMORY_0BA7/_0BA8)
IMAGES: dict[str, dict[str, tuple[int, int]]] = {
    "0ba7": {
        "I": (923, 3),
        "AI": (926, 16),
        "Q": (942, 2),
        "AQ": (944, 4),
        "M": (948, 4),
        "AM": (952, 32),
    },
    "0ba8": {
        "I": (1024, 8),
        "AI": (1032, 32),
        "Q": (1064, 8),
        "AQ": (1072, 32),
        "M": (1104, 14),
        "AM": (1118, 128),
        "NI": (1246, 16),
        "NAI": (1262, 128),
        "NQ": (1390, 16),
        "NAQ": (1406, 64),
    },
}
IMAGES["8_x"] = IMAGES["0ba8"]
VM_SIZE = {"0ba7": 984, "0ba8": 1470, "8_x": 1470}  # bytes of DB1 (the same binding's SIZE)
SERVER_TSAP = {"0ba7": 0x1000, "0ba8": 0x2000, "8_x": 0x2000}  # READINGS.md row 1
NETWORK_INPUTS = ("NI", "NAI")
_NAME = re.compile(r"(NAI|NAQ|NI|NQ|AI|AQ|AM|I|Q|M)([0-9]+)")


class LogoSimulator(S7Simulator):
    """A LOGO! of one generation, with its blocks set and read by their LOGO! names."""

    def __init__(self, generation: str = "0ba8", *, server_tsaps: set[int] | None = None) -> None:
        """Prepare the VM of `generation` ("0ba7", "0ba8", "8_x"); accept `server_tsaps`."""
        super().__init__(
            pdu_size=240,
            szl=False,
            has_clock=False,
            dbs={1: VM_SIZE[generation]},
            remote_tsap=SERVER_TSAP[generation],
        )
        self.generation = generation
        self.rack = self.slot = None  # type: ignore[assignment]  # a LOGO! has neither
        # The server TSAPs of the connections configured in the LOGO! (READINGS.md row 1)
        self.server_tsaps = server_tsaps or {SERVER_TSAP[generation]}
        # "kept": a network input written stays until written again; "rewritten": its block
        # takes the value from elsewhere and the LOGO! rewrites its image every cycle (row 4)
        self.network_inputs = "kept"
        self._program: dict[int, int] = {}  # network input bytes as the LOGO! program sets them

    @property
    def form_fields(self) -> dict[str, str]:
        """The connection options the demo prints for this LOGO!."""
        tsap = min(self.server_tsaps)
        return {"generation": self.generation, "remote_tsap": f"{tsap >> 8:02X}.{tsap & 0xFF:02X}"}

    def accepts(self, called_tsap: bytes | None) -> bool:
        """True for the server TSAP of a configured connection; a LOGO! has no rack/slot."""
        return called_tsap is not None and int.from_bytes(called_tsap, "big") in self.server_tsaps

    def count(self, pdu: bytes) -> None:
        """Count a request; a cycle has passed since the last one: rewrite what it rewrites."""
        if self.network_inputs == "rewritten":
            for at, value in self._program.items():
                self.set_db(1, at, bytes([value]))
        super().count(pdu)

    def _place(self, name: str) -> tuple[int, int | None]:
        """Return a block's VM byte and bit (None for an analog word)."""
        match = _NAME.fullmatch(name.upper())
        if match is None:
            raise ValueError(f"{name!r} is no LOGO! block")
        kind, number = match[1], int(match[2])
        if kind not in IMAGES[self.generation]:
            raise ValueError(f"a LOGO! {self.generation} has no {kind}")
        start, size = IMAGES[self.generation][kind]
        analog = kind.startswith("A") or kind.startswith("NA")
        offset = (number - 1) * 2 if analog else (number - 1) // 8
        if number < 1 or offset + (2 if analog else 1) > size:
            raise ValueError(f"{name} lies outside the {kind} image")
        return start + offset, None if analog else (number - 1) % 8

    def set_block(self, name: str, value: int | bool, *, by_program: bool = False) -> None:
        """Set a block's image (I3, AI1, NI2...); `by_program`: as the program sets it (row 4)."""
        at, bit = self._place(name)
        if bit is None:
            self.set_db(1, at, struct.pack(">h", int(value)))
        else:
            old = self.get_db(1, at, 1)[0]
            self.set_db(1, at, bytes([old | 1 << bit if value else old & ~(1 << bit)]))
        if by_program and name.upper().startswith(NETWORK_INPUTS):
            for byte in range(at, at + (1 if bit is not None else 2)):
                self._program[byte] = self.get_db(1, byte, 1)[0]

    def get_block(self, name: str) -> int | bool:
        """Return a block's image value: a bit, or a signed word."""
        at, bit = self._place(name)
        if bit is None:
            return int(struct.unpack(">h", self.get_db(1, at, 2))[0])
        return bool(self.get_db(1, at, 1)[0] >> bit & 1)
