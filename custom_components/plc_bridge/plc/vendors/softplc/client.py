"""The SoftPLC WEB.TLM client: every point of a poll in one POST /dt, writes in one PUT /dt."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from datetime import datetime
import logging
import time
from typing import ClassVar

import aiohttp

from ...client import PlcClient
from ...errors import (
    PlcAddressError,
    PlcAuthenticationError,
    PlcConnectionError,
    PlcError,
    PlcProtocolError,
    PlcTimeoutError,
    PlcTlsError,
    PlcValueError,
    PlcWriteRefusedError,
)
from ...http import HttpTransport
from ...shifting import ELEMENTS
from ...types import (
    ConnectionConfig,
    DeviceInfo,
    Footprint,
    Point,
    PointResult,
    ReadResult,
    TlsMode,
    Value,
    ValueKind,
)
from .address import Address, parse_address, shift
from .codec import KINDS, TYPES, check_value, data_type
from .document import MAX_REPLY, request_body
from .exchange import Answers, Busy, Patience, Refused, exchange, send
from .planner import Key, Locator, ReadItem, plan
from .reading import Wanted, result_of, wanted_of
from .tls import CERTIFICATE, client_context, has_certificate, pem_options, resolve_material
from .writing import confirm, write_items

_LOGGER = logging.getLogger(__name__)

WORD_BITS = 16
"""Bits of a datatable word: footprints count bits, so that two bits of one word are apart."""
MAX_PARSED = 65536
"""Points whose parsed address a client keeps (a poll parses only what it has not seen)."""


def check_writable(address: Address) -> None:
    """Refuse what no PUT of the manual can write: the status word of a T, C or R element."""
    if address.is_opaque and address.bit is not None:
        raise PlcAddressError(
            f"{address.text}: without a colon the PLC decides which word this is, and a bit is "
            f"written back into the word it was read from; write it as {address.type}"
            f"{address.file}:<element>/{address.bit}"
        )
    if address.type in ("T", "C", "R") and address.word == 0:
        raise PlcAddressError(
            f"{address.text}: the manual has no word name for a {address.type} element's status "
            "word, so it cannot be written; write its PRE/ACC (LEN/POS) words"
        )


class SoftplcClient(PlcClient):
    """A SoftPLC runtime through its WEB.TLM REST server (XML)."""

    vendor: ClassVar[str] = "softplc"
    shift_units: ClassVar[tuple[str, ...]] = (ELEMENTS,)
    default_port: ClassVar[int] = 80
    default_tls: ClassVar[TlsMode] = TlsMode.NONE
    tls_modes: ClassVar[tuple[TlsMode, ...]] = (
        TlsMode.NONE,
        TlsMode.PIN,
        TlsMode.VERIFY,
        TlsMode.OFF,
    )
    needs_credentials: ClassVar[bool] = False
    credential_option: ClassVar[str | None] = CERTIFICATE  # PUTs authenticate by certificate
    data_types: ClassVar[tuple[str, ...]] = TYPES
    probe_interval: ClassVar[float] = 60.0  # refused addresses are asked again this often

    def __init__(
        self, config: ConnectionConfig, session: aiohttp.ClientSession | None = None
    ) -> None:
        """Keep the settings; the transport (and its client certificate) is made on first use."""
        super().__init__(config, session)
        self._http: HttpTransport | None = None
        self._refused: dict[Key, PlcError] = {}
        self._parsed: dict[Point, Wanted | PlcError] = {}
        self._probed_at = -float("inf")
        self._unread: set[Point] = set()  # points whose write was logged as not read back
        self._patience = Patience(config.poll_interval)  # a busy PLC is waited for this long
        self._certificate = has_certificate(config) and config.tls is not TlsMode.NONE

    @classmethod
    def validate_options(cls, options: Mapping[str, object]) -> dict[str, str | int | bool]:
        """Return the client certificate and key (pasted PEM or absolute paths), or nothing."""
        return dict(pem_options(options))

    @classmethod
    def validate_point(cls, point: Point) -> Point:
        """Return the point in the manual's request form (N7:3, I1:3; tags and I1 as typed)."""
        address = parse_address(point.address)
        return Point(address.text, data_type(address, point.data_type))

    @classmethod
    def shift_point(cls, point: Point, by: int, unit: str, part: str = "") -> Point:
        """Return the point moved by elements of its file (N7:10 + 5 = N7:15)."""
        return cls.validate_point(Point(shift(point.address, by, unit), point.data_type))

    @classmethod
    def footprint(cls, point: Point) -> Footprint:
        """The file and the bits a point covers (a word its 16 bits); a tag or PD word its name.

        Names are folded: whether the descriptor table folds case is open (READINGS.md), and a
        fold only makes the write guard refuse more.
        """
        address = parse_address(point.address)
        if address.is_tag or address.is_named_word:
            return Footprint(address.text.casefold(), 0, WORD_BITS)
        start = (address.element * address.words + address.word) * WORD_BITS
        if address.bit is None:
            return Footprint(f"{address.type}{address.file}", start, start + WORD_BITS)
        return Footprint(
            f"{address.type}{address.file}", start + address.bit, start + address.bit + 1
        )

    @classmethod
    def write_footprint(cls, point: Point) -> Footprint:
        """A bit's whole word: a PUT writes whole words (the bit's word is read, then written)."""
        covers = cls.footprint(point)
        start = covers.start - covers.start % WORD_BITS
        return Footprint(covers.area, start, max(covers.end, start + WORD_BITS))

    @classmethod
    def address_writable(cls, point: Point) -> bool:
        """False for the input file I and the status words of T, C and R elements."""
        address = parse_address(point.address)
        try:
            check_writable(address)
        except PlcAddressError:
            return False
        return address.type != "I"

    @classmethod
    def validate_value(cls, point: Point, value: Value) -> Value:
        """Return the value checked for the point's type (decimal or 0x hex for words)."""
        address = parse_address(point.address)
        check_writable(address)
        return check_value(data_type(address, point.data_type), value, address.text)

    @classmethod
    def value_kind(cls, point: Point) -> ValueKind | None:
        """Return what the point holds."""
        try:
            return KINDS[data_type(parse_address(point.address), point.data_type)]
        except PlcAddressError:
            return None

    @classmethod
    def requests_for(cls, points: Sequence[Point]) -> int:
        """One POST a poll, whatever the points (refused items cost more only while found)."""
        return 1 if points else 0

    @classmethod
    def items_for(cls, points: Sequence[Point]) -> int:
        """Return how many `<data>` items one poll of these points asks for."""
        addresses = []
        for point in points:
            try:
                addresses.append(parse_address(point.address))
            except PlcAddressError:
                continue
        return len(plan(addresses))

    async def _transport(self) -> HttpTransport:
        """Return the transport; with a client certificate, over an SSL context presenting it."""
        if self._http is None:
            context = await client_context(self.config) if self._certificate else None
            self._http = HttpTransport(
                self.config, self.session, self.metrics, ssl_context=context, max_body=MAX_REPLY
            )
        return self._http

    async def _send(self, method: str, items: Sequence[ReadItem], answers: Answers) -> None:
        """Exchange items with the PLC (halving around refused ones)."""
        transport = await self._transport()
        try:
            await exchange(
                transport,
                method,
                items,
                answers,
                certificate=self._certificate,
                patience=self._patience,
            )
        except PlcConnectionError as err:
            await self._refused_certificate(err)
            raise

    async def _refused_certificate(self, err: PlcConnectionError) -> None:
        """Raise PlcAuthenticationError when the PLC drops us for our client certificate.

        Under TLS 1.3 a server refuses a client certificate after the handshake, and the
        client sees only a closed connection. One request without the certificate tells:
        answered, the link is fine and the certificate is what the PLC refuses.
        """
        if not self._certificate or isinstance(err, PlcTimeoutError | PlcTlsError | Busy):
            return
        bare = HttpTransport(self.config, self.session, self.metrics)
        try:
            await bare.request("GET", "/dt")
        except PlcError:
            return
        raise PlcAuthenticationError(
            "the PLC closes every connection that presents the client certificate: it does not "
            "trust it"
        ) from None

    async def connect(self) -> DeviceInfo:
        """Ask for the file listing (GET /dt): the PLC answers (reads need no certificate)."""
        transport = await self._transport()
        try:
            status, _body = await send(
                transport,
                "GET",
                "/dt",
                None,
                certificate=self._certificate,
                patience=self._patience,
            )
        except PlcConnectionError as err:
            await self._refused_certificate(err)
            raise
        if status != 200:
            raise PlcProtocolError(f"the PLC answered GET /dt with HTTP {status}, not its files")
        return DeviceInfo(
            vendor=self.vendor,
            model="SoftPLC WEB.TLM",
            name="SoftPLC",
            extra={"writes_with_certificate": "yes" if self._certificate else "no"},
        )

    @classmethod
    def resolve_options(
        cls, folder: str, submitted: Mapping[str, object], stored: Mapping[str, object]
    ) -> dict[str, str]:
        """Return the certificate and key, paths made absolute in `folder` (`resolve_material`)."""
        return resolve_material(folder, submitted, stored)

    async def check_access(self) -> None:
        """Check the client certificate a write would present (`check_certificate`)."""
        await self.check_certificate()

    async def check_certificate(self) -> None:
        """PUT nothing (`<files/>`: no item, nothing written) to see the certificate taken.

        A PLC with enable_put_auth refuses an untrusted certificate here, so a form finds out
        before the first write; any answer but 401/403 lets it pass. Not part of connect: a
        refused certificate must not stop the reads.
        """
        if not self._certificate:
            return
        try:
            await send(await self._transport(), "PUT", "/dt", request_body(()), certificate=True)
        except PlcConnectionError as err:
            await self._refused_certificate(err)
            raise

    async def _read(self, points: Sequence[Point], *, poll: bool) -> ReadResult:
        """Read every point with one POST; refused addresses are asked again once a minute."""
        values: dict[Point, PointResult] = {}
        wanted: list[Wanted] = []
        parsed = self._parsed
        if len(parsed) > MAX_PARSED:
            parsed.clear()
        for point in points:
            want = parsed.get(point)
            if want is None:
                want = parsed[point] = wanted_of(point)
            if isinstance(want, PlcError):
                values[point] = PointResult(error=want)
            else:
                wanted.append(want)
        refused = dict(self._refused) if poll else {}
        if refused and time.monotonic() - self._probed_at >= self.probe_interval:
            refused = {}
        if poll and not refused:  # this poll asks for every address: it is the probe
            self._refused, self._probed_at = {}, time.monotonic()
        asked = [want.address for want in wanted if not refused or want.key not in refused]
        answers, items = await self.fetch(asked)
        find = Locator(items).find
        for want in wanted:
            error = refused.get(want.key) if refused else None
            item = None if error else find(want.address)
            if item is None:
                values[want.point] = PointResult(error=error or PlcProtocolError("not planned"))
                continue
            result = values[want.point] = result_of(want, item, answers[item])
            refusal = isinstance(answers[item], Refused) and item.count in (None, 1)
            if poll and result.error and refusal:
                self._refused[want.key] = result.error
        return ReadResult(values=values)

    async def fetch(self, addresses: Sequence[Address]) -> tuple[Answers, list[ReadItem]]:
        """Read addresses; a refused range is asked again element by element.

        Returns the answers and the items to look an address up in (the pieces in place of
        the ranges they split: no two overlap).
        """
        items = plan(addresses)
        answers: Answers = {}
        await self._send("POST", items, answers)
        pieces: list[ReadItem] = []
        for item in items:
            if isinstance(answers[item], Refused) and item.count not in (None, 1):
                holds = Locator([item]).find
                inside = [a for a in addresses if holds(a) is not None]
                pieces.extend(plan(inside, max_gap=-1))
        if pieces:
            await self._send("POST", pieces, answers)
        split = {
            item
            for item in items
            if isinstance(answers[item], Refused) and item.count not in (None, 1)
        }
        final = [*pieces, *(item for item in items if item not in split)]
        if len(final) > 1 and all(isinstance(answers[item], Refused) for item in final):
            raise PlcProtocolError(
                f"the PLC refused every item of the request: {answers[final[0]]}"
            )
        return answers, final

    async def _write(self, values: Mapping[Point, Value]) -> dict[Point, PointResult]:
        """Write every value with one PUT (bits: their words are read first, in one POST)."""
        results: dict[Point, PointResult] = {}
        plan_ = await write_items(self, values, results)
        answers: Answers = {}
        await self._send("PUT", list(plan_), answers)
        for item, writes in plan_.items():
            answer = answers[item]
            for sent in writes:
                if isinstance(answer, PlcError):
                    error: PlcError = (
                        PlcWriteRefusedError(str(answer)) if isinstance(answer, Refused) else answer
                    )
                    results[sent.point] = PointResult(error=error)
                else:
                    results[sent.point], unread = confirm(answer, sent)
                    if unread:
                        self._not_read_back(sent.point, unread)
        return results

    def _not_read_back(self, point: Point, why: str) -> None:
        """Log a write done but not confirmed: once per point, as a warning."""
        if point in self._unread or len(self._unread) >= MAX_PARSED:
            return
        self._unread.add(point)
        _LOGGER.warning(
            "%s on %s: written, not read back (%s)", point.address, self.config.host, why
        )

    @property
    def can_set_clock(self) -> bool:
        """False: WEB.TLM serves the datatable only, no clock."""
        return False

    async def read_clock(self) -> datetime:
        """WEB.TLM has no clock service."""
        raise PlcProtocolError("SoftPLC's WEB.TLM has no clock service")

    async def set_clock(self, when: datetime) -> None:
        """WEB.TLM has no clock service."""
        raise PlcWriteRefusedError("SoftPLC's WEB.TLM has no clock service")

    async def close(self) -> None:
        """Release the client's own session (WEB.TLM has no sessions)."""
        self._http = None
        await self._close_own_session()


__all__ = ["PlcValueError", "SoftplcClient"]
