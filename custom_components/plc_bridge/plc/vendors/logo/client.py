"""Siemens LOGO! 0BA7, 0BA8 and 8.x over the S7 transport: LOGO! addresses read from DB1.

The S7 client does the work (link, PDU-packed reads, writes, reconnects); this one resolves
LOGO! addresses to DB1 for the generation configured, refuses writes a LOGO! would overwrite
before anything is sent, and reads a network input back after writing it (READINGS row 4).

The address checks the forms call are class methods. Bound to a PLC's options (`configured`,
which the forms, the pasted file, the actions and the entry's client use) they refuse a block the
configured generation lacks (NI1 on a 0BA7); unbound, they accept what some generation has.
Footprints are in block terms (a block's image never overlaps V0..V849).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import ClassVar

import aiohttp

from ...errors import PlcAddressError, PlcOptionError, PlcValueError, PlcWriteRefusedError
from ...shifting import BLOCKS, BYTES
from ...types import ConnectionConfig, DeviceInfo, Footprint, Point, PointResult, Value
from ..s7 import S7Client
from ..s7.address import Variable
from ..s7.codec import check_value, span_of
from ..s7.planner import Span, plan_reads
from .address import DATA_TYPES, GENERATIONS, MODELS, parse, refusal, shift, variable
from .options import s7_options, validate_options

PLANNED_GENERATION = "0ba8"  # a class plans without a PLC: for the most common generation
PDU = 240  # every LOGO! generation negotiates 240 bytes (READINGS row 2)


class LogoClient(S7Client):
    """One LOGO! by TSAP; its blocks and VM read in the S7 client's packed multi-reads."""

    vendor: ClassVar[str] = "logo"
    data_types: ClassVar[tuple[str, ...]] = DATA_TYPES
    requested_pdu: ClassVar[int] = PDU
    checked_generation: ClassVar[str | None] = None
    """The generation whose blocks the class methods accept (None: any generation's)."""
    shift_units: ClassVar[tuple[str, ...]] = (BYTES, BLOCKS)

    def __init__(
        self, config: ConnectionConfig, session: aiohttp.ClientSession | None = None
    ) -> None:
        """Keep the settings; the S7 client connects by the TSAPs of the LOGO! options."""
        self._generation = str(validate_options(config.options)["generation"])
        super().__init__(replace(config, options=s7_options(config.options)), session)
        self.config = config

    @property
    def generation(self) -> str:
        """The LOGO! generation configured (0ba7, 0ba8, 8_x)."""
        return self._generation

    def _variable(self, point: Point) -> Variable:
        """Resolve a point in this LOGO!'s VM map."""
        return variable(point, self._generation)

    @classmethod
    def validate_options(cls, options: Mapping[str, object]) -> dict[str, str | int | bool]:
        """Return generation and TSAPs normalized; raise PlcOptionError naming the field."""
        return validate_options(options)

    @classmethod
    def configured(cls, options: Mapping[str, object]) -> type[LogoClient]:
        """Return the class that accepts only the configured generation's blocks."""
        try:
            generation = str(validate_options(options)["generation"])
        except PlcOptionError:
            return cls
        return GENERATION_CLASSES[generation]

    @classmethod
    def validate_point(cls, point: Point) -> Point:
        """Return the point as LOGO!Soft Comfort writes it (VB100, V10.3); raise PlcAddressError.

        A class bound to a generation (`configured`) refuses the blocks that generation lacks
        (NI1 on a 0BA7); the others accept a block some generation has.
        """
        found = parse(point)
        generation = cls.checked_generation or PLANNED_GENERATION
        return Point(found.text, variable(point, generation).data_type)

    @classmethod
    def shift_point(cls, point: Point, by: int, unit: str, part: str = "") -> Point:
        """Return the point moved by VM bytes (VW10 + 24 = VW34) or block numbers (I1 + 4)."""
        return shift(point, by, unit)

    @classmethod
    def footprint(cls, point: Point) -> Footprint:
        """A block by number (bits, or words of 16 bits); VM by bit, as S7 counts it."""
        found = parse(point)
        if found.block != "V":
            size = 16 if found.block.startswith(("A", "NA")) else 1
            first = (found.number - 1) * size
            return Footprint(f"logo:{found.block}", first, first + size)
        resolved = variable(point, PLANNED_GENERATION)
        start = resolved.start * 8
        if resolved.bit is not None:
            return Footprint("logo:V", start + resolved.bit, start + resolved.bit + 1)
        return Footprint("logo:V", start, start + resolved.size * 8)

    @classmethod
    def address_writable(cls, point: Point) -> bool:
        """True for VM and network inputs (NI, NAI) only."""
        return parse(point).writable

    @classmethod
    def validate_value(cls, point: Point, value: Value) -> Value:
        """Refuse a block the LOGO! sets itself; check the value for the type; PlcValueError."""
        found = parse(point)
        reason = refusal(found)
        if reason is not None:
            raise PlcValueError(
                f"{found.text} cannot be written: {reason}. A LOGO! takes writes to V memory "
                "and network inputs (NI, NAI) only"
            )
        return check_value(variable(point, PLANNED_GENERATION), value)

    @classmethod
    def requests_for(cls, points: Sequence[Point], pdu_size: int = PDU) -> int:
        """Round trips of a typical poll of a LOGO! 8 (PDU 240): the packed reads."""
        return cls._requests(points, PLANNED_GENERATION, pdu_size)

    @staticmethod
    def _requests(points: Sequence[Point], generation: str, pdu_size: int) -> int:
        """Round trips of one poll of the points in a generation's map."""
        needs: set[Span] = set()
        for point in points:
            try:
                needs.add(span_of(variable(point, generation)))
            except PlcAddressError:
                continue
        return len(plan_reads(needs, pdu_size))

    def planned_requests(self, points: Sequence[Point]) -> int:
        """Round trips of one poll in this LOGO!'s map, at the PDU it negotiated."""
        return self._requests(points, self._generation, self.pdu_size)

    @property
    def can_set_clock(self) -> bool:
        """A LOGO! answers no S7 clock functions (READINGS row 5)."""
        return False

    async def connect(self) -> DeviceInfo:
        """Open the session; a LOGO! without SZL lists is named by its generation."""
        found = await super().connect()
        model = found.model if "order_code" in found.extra else MODELS[self._generation]
        return replace(found, model=model, extra=found.extra | {"generation": self._generation})

    async def _write(self, values: Mapping[Point, Value]) -> dict[Point, PointResult]:
        """Write; then read the network inputs written back: one the LOGO! lost fails."""
        results = await super()._write(values)
        network = [
            point
            for point, result in results.items()
            if result.ok and parse(point).block in ("NI", "NAI")
        ]
        if not network:
            return results
        back = (await self._read(network, poll=False)).values
        for point in network:
            kept = back[point]
            if not kept.ok:
                results[point] = PointResult(error=kept.error)
            elif kept.value != values[point]:
                results[point] = PointResult(
                    error=PlcWriteRefusedError(
                        f"{parse(point).text} reads {kept.value!r} after {values[point]!r} was "
                        "written: the LOGO! program does not take this network input from "
                        "Home Assistant (its block takes its value from another partner)"
                    )
                )
        return results


GENERATION_CLASSES: dict[str, type[LogoClient]] = {
    generation: type(
        f"LogoClient{generation.upper()}",
        (LogoClient,),
        {"checked_generation": generation, "__doc__": f"A LOGO! {generation}'s address checks."},
    )
    for generation in GENERATIONS
}
"""The client classes whose address checks know one generation (see `configured`)."""
