"""The client's S7 session: one job at a time, reopened after a loss at most once a backoff window.

A lost connection fails the poll that meets it (PlcConnectionError) and is logged once at
warning; the next poll reconnects at once, and while that fails, attempts are spaced by an
exponential backoff (the client's `reconnect_delay`), logged at debug. The first success resets
the backoff and logs once at info.

The window never outlasts the poll interval, so every poll makes one attempt at most and the
first poll after the PLC is back reconnects: it is capped at the interval less a second (a
scheduler may start a poll up to a second early: Home Assistant aligns polls to whole seconds),
but never below half the interval, and it counts from the start of the failed attempt.

A request waits about one poll interval for its answer (`request_timeout`): at least the
client's `shortest_timeout`, at most the configured timeout. A connection that went half-open
(the PLC vanished without a reset) is then found by the poll that meets it, and the next poll
opens a new one, instead of a fixed 10 s wait holding every entity past several polls; a PLC
that answers later than an interval but within that bound is still read.
"""

from __future__ import annotations

import asyncio
from collections.abc import Awaitable, Callable
import logging
import time

from ...errors import PlcConnectionError, PlcError
from ...types import ClientMetrics, ConnectionConfig
from .link import Endpoint, S7Link
from .planner import DEFAULT_PDU

_LOGGER = logging.getLogger(__name__)


def longest_wait(longest: float, poll_interval: float) -> float:
    """Return the longest reconnect wait a poll interval allows (see the module docstring)."""
    return min(longest, max(poll_interval - 1.0, poll_interval / 2))


def request_timeout(config: ConnectionConfig, shortest: float) -> float:
    """Return a request's wait: a poll interval, at least `shortest`, at most the timeout."""
    return min(config.timeout, max(shortest, config.poll_interval))


class Session:
    """Owns the link, the lock every job takes, and the reconnect backoff."""

    def __init__(
        self,
        config: ConnectionConfig,
        ends: Endpoint,
        metrics: ClientMetrics,
        delays: Callable[[], tuple[float, float]],
        shortest_timeout: float,
    ) -> None:
        """Keep what a connection needs; `delays` returns the first and longest wait."""
        self._config, self._ends, self._metrics, self._delays = config, ends, metrics, delays
        self.timeout = request_timeout(config, shortest_timeout)
        self._where = f"{config.host}:{config.port}"
        self._link: S7Link | None = None
        self._lock = asyncio.Lock()
        self._delay = 0.0
        self._retry_at = 0.0
        self._lost = False
        self.pdu_size = DEFAULT_PDU  # the last size a PLC negotiated
        self.opened = 0  # links opened so far: a new one may be another CPU, or a new program

    async def run[T](
        self, job: Callable[[S7Link], Awaitable[T]], requested_pdu: int, *, fresh: bool = False
    ) -> T:
        """Run a job on the link (a new one when `fresh`); a broken link fails it, is dropped."""
        async with self._lock:
            link = await self._open(requested_pdu) if fresh else await self._ready(requested_pdu)
            try:
                return await job(link)
            except PlcConnectionError as err:
                self._note_lost(err)
                await self._drop()
                raise

    async def close(self) -> None:
        """Close the link, after the job under way."""
        async with self._lock:
            await self._drop()

    async def _ready(self, requested_pdu: int) -> S7Link:
        """Return the open link, or reconnect: at most once per backoff window."""
        if self._link is not None and self._link.usable:
            return self._link
        await self._drop()
        started = time.monotonic()
        wait = self._retry_at - started
        if wait > 0:
            raise PlcConnectionError(f"{self._where} is unreachable; next attempt in {wait:.1f} s")
        try:
            return await self._open(requested_pdu)
        except PlcError as err:
            first, longest = self._delays()
            longest = longest_wait(longest, self._config.poll_interval)
            self._delay = min(longest, self._delay * 2 if self._delay else first)
            self._retry_at = started + self._delay
            self._note_lost(err)
            raise

    async def _open(self, requested_pdu: int) -> S7Link:
        """Open a new link; on success forget the backoff and say so once if it was lost."""
        await self._drop()
        config = self._config
        link = S7Link(config.host, config.port, self._ends, self.timeout, self._metrics)
        await link.open(requested_pdu)
        self._link, self.pdu_size = link, link.pdu_size
        self._delay, self._retry_at = 0.0, 0.0
        self.opened += 1
        if self._lost:
            self._lost = False
            _LOGGER.info("Connection to S7 PLC %s restored", self._where)
        return link

    def _note_lost(self, err: PlcError) -> None:
        """Log a lost connection once at warning; the attempts after it at debug."""
        if self._lost:
            _LOGGER.debug("S7 PLC %s still unreachable: %s", self._where, err)
            return
        self._lost = True
        _LOGGER.warning("Lost connection to S7 PLC %s: %s", self._where, err)

    async def _drop(self) -> None:
        """Close the current link, if any."""
        if self._link is not None:
            link, self._link = self._link, None
            await link.close()
