"""Whether an S7 CPU answers ISO-on-TCP at a host: a connection request that gets a confirm."""

from __future__ import annotations

import asyncio
import contextlib
from typing import Any

import aiohttp

from .link import LOCAL_TSAP, PG

SLOTS = (1, 2)
"""The CPU slots asked, rack 0: an S7-1200/1500 (the connection page's default), an S7-300/400."""
_CONNECTION_CONFIRM = 0xD0


def connection_request(called_tsap: int) -> bytes:
    """Return a TPKT with a COTP connection request (RFC 1006, ISO 8073 class 0) for a TSAP."""
    cotp = bytes((0xE0, 0, 0, 0, 1, 0))  # CR, destination 0, source 1, class 0
    cotp += bytes((0xC0, 1, 0x0A))  # TPDU size 1024
    cotp += bytes((0xC1, 2)) + LOCAL_TSAP.to_bytes(2, "big")
    cotp += bytes((0xC2, 2)) + called_tsap.to_bytes(2, "big")
    frame = bytes((len(cotp),)) + cotp
    return bytes((3, 0)) + (4 + len(frame)).to_bytes(2, "big") + frame


async def confirms(host: str, port: int, called_tsap: int) -> bool:
    """Send one connection request on a new TCP connection; True when a confirm comes back."""
    reader, writer = await asyncio.open_connection(host, port)
    try:
        writer.write(connection_request(called_tsap))
        await writer.drain()
        header = await reader.readexactly(4)
        if header[0] != 3 or int.from_bytes(header[2:4], "big") < 6:
            return False
        cotp = await reader.readexactly(int.from_bytes(header[2:4], "big") - 4)
        return cotp[1] & 0xF0 == _CONNECTION_CONFIRM
    finally:
        writer.close()
        with contextlib.suppress(OSError):
            await writer.wait_closed()


async def answers(
    host: str, port: int, session: aiohttp.ClientSession, timeout: float
) -> dict[str, Any] | None:
    """The slot at which a CPU at rack 0, slot 1 or 2, confirms a PG connection (no S7 job sent).

    A CPU refuses a TSAP it does not serve by closing or with a disconnect request: then the
    next slot is asked, within the same timeout. `session` is not used (no HTTP).
    """
    try:
        async with asyncio.timeout(timeout):
            for slot in SLOTS:
                with contextlib.suppress(asyncio.IncompleteReadError, ConnectionError):
                    if await confirms(host, port, PG << 8 | slot):
                        return {"rack": 0, "slot": slot}
    except OSError:  # TimeoutError is one; so is a refused connection
        return None
    return None
