"""Whether a LOGO! answers at a host: a COTP connection confirmed at a LOGO! server TSAP.

An S7-300..1500 CPU serves rack/slot TSAPs (01.xx to 03.xx) and refuses 10.00 and 20.00; a LOGO!
confirms the server TSAP of a connection configured in LOGO!Soft Comfort. Each generation's
default is asked in turn, within one timeout; no S7 job is sent.
"""

from __future__ import annotations

import asyncio
import contextlib
from typing import Any

import aiohttp

from ..s7.link import parse_tsap
from ..s7.probe import confirms
from .options import DEFAULT_TSAPS

ASKED = ("0ba8", "0ba7")  # 8_x shares 0BA8's defaults


async def answers(
    host: str, port: int, session: aiohttp.ClientSession, timeout: float
) -> dict[str, Any] | None:
    """The generation and TSAPs whose default server TSAP the host confirms; None if none."""
    try:
        async with asyncio.timeout(timeout):
            for generation in ASKED:
                local, remote = DEFAULT_TSAPS[generation]
                with contextlib.suppress(asyncio.IncompleteReadError, ConnectionError):
                    if await confirms(host, port, parse_tsap(remote, "remote_tsap")):
                        return {
                            "generation": generation,
                            "local_tsap": local,
                            "remote_tsap": remote,
                        }
    except OSError:  # TimeoutError is one; so is a refused connection
        return None
    return None
