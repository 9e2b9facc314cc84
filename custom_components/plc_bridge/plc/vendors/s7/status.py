"""The CPU status a poll reports: the state (SZL 0x0424) and the clock, read once an interval.

Each is a USERDATA round trip of its own, so neither goes out at every poll: both are read at the
first poll of a link and then once every `status_interval` (60 s), and kept in between. What a
PLC refuses (an S7-200 or LOGO! has no SZL 0x0424, some CPs no clock) is not asked again on the
same connection; a new one asks again.
"""

from __future__ import annotations

from datetime import datetime
import logging
import math
import time
from zoneinfo import ZoneInfo

from ...errors import PlcProtocolError
from ...types import PlcStatus
from .link import S7Link
from .protocol import SZL_STATE, cpu_mode

_LOGGER = logging.getLogger(__name__)


class StatusReader:
    """Reads the CPU state and clock at most once per interval, keeping them in between."""

    def __init__(self, zone: ZoneInfo, where: str) -> None:
        """Report clocks in `zone`; name the PLC `where` in log lines."""
        self._zone, self._where = zone, where
        self._state_known = True  # False once the PLC refused SZL 0x0424
        self._clock_known = True  # False once the PLC refused or garbled its clock
        self._mode: str | None = None
        self._clock: datetime | None = None
        self._read_at = -math.inf  # monotonic time of the last status read

    def forget(self) -> None:
        """A new link, maybe another CPU: ask for everything again, at the next poll."""
        self._state_known = self._clock_known = True
        self._read_at = -math.inf

    def clock_due(self) -> None:
        """Read the status at the next poll (the clock was just set)."""
        self._read_at = -math.inf

    async def read(self, link: S7Link, interval: float) -> PlcStatus:
        """Return the state and clock as last read (read again once `interval` passed)."""
        now = time.monotonic()
        if now - self._read_at >= interval:
            self._mode = await self._read_mode(link)
            if self._clock_known:
                await self._read_clock(link)
            self._read_at = now
        return PlcStatus(mode=self._mode, clock=self._clock)

    async def _read_clock(self, link: S7Link) -> None:
        """Read and keep the clock (one request); a PLC that cannot is not asked again."""
        try:
            self._clock = (await link.get_clock()).replace(tzinfo=self._zone)
        except PlcProtocolError as err:
            _LOGGER.debug("%s reports no clock, not asking again: %s", self._where, err)
            self._clock_known, self._clock = False, None

    async def _read_mode(self, link: S7Link) -> str | None:
        """Return the operating mode (one SZL request); None where the PLC cannot tell."""
        if not self._state_known:
            return None
        try:
            return cpu_mode(await link.read_szl(SZL_STATE))
        except PlcProtocolError as err:
            _LOGGER.debug("%s reports no CPU state, not asking again: %s", self._where, err)
            self._state_known = False
            return None
