"""The S7-200 SMART Web API session: login, token, one renewal, refusals told by structure.

The manual defines no session error code (its error page is missing); how a refusal is read is
in `WebSession._call` and READINGS.md in simulators/s7_smart.
"""

from __future__ import annotations

import asyncio
import hashlib
import logging
from typing import Any

import aiohttp

from ...client import PlcClient
from ...errors import PlcError, PlcProtocolError
from ...http import HttpTransport
from ...types import ConnectionConfig
from .errors import (
    RpcError,
    login_error,
    permission_error,
    request_error,
    session_error,
    stop_error,
)
from .rpc import WebApi

_LOGGER = logging.getLogger(__name__)

LOGOUT_TIMEOUT = 2.0


class WebSession(PlcClient):
    """The login and the calls of one Web API user; the client adds reads and writes."""

    def __init__(
        self, config: ConnectionConfig, session: aiohttp.ClientSession | None = None
    ) -> None:
        """Keep the settings; the transport is made and the login done on first use."""
        super().__init__(config, session)
        self._transport: HttpTransport | None = None
        self._api: WebApi | None = None
        self._token: str | None = None
        self._login_lock = asyncio.Lock()
        self._logins = 0  # successful logins so far: concurrent callers share one
        self._mode: str | None = None  # the operating mode the last status block reported
        self._can_write = True  # what get_permission said at connect (manual 7)

    def _http(self) -> HttpTransport:
        """Return the transport, made on first use."""
        if self._transport is None:
            self._transport = HttpTransport(
                self.config, self.session, self.metrics, request_interval=self.request_interval
            )
        return self._transport

    async def _send(self, method: str, params: Any) -> dict[str, Any]:
        """Send one call with the token held; return its result, raise RpcError for a refusal."""
        if self._api is None:
            self._api = WebApi(self._http(), self.config.host, self.config.poll_interval)
        return await self._api.call(method, params, self._token)

    async def close(self) -> None:
        """Log out (a failure is of no consequence) and release the client's own session."""
        if self._transport is not None and self._token is not None:
            try:
                # Short: an unreachable PLC must not hold up Home Assistant's unload or shutdown.
                async with asyncio.timeout(LOGOUT_TIMEOUT):
                    await self._send("logout", None)
            except (PlcError, RpcError, TimeoutError) as err:
                _LOGGER.debug("Logout from %s failed: %s", self.config.host, err)
        self._token = None
        self._transport = None
        self._api = None
        await self._close_own_session()

    async def _login(self, seen: int | None = None) -> None:
        """Log in with the password's sha512 hex digest and keep the token.

        Single-flight: a caller that saw `seen` logins before its call failed logs in only if
        nobody has since; concurrent callers share the one new login (a second login would end
        the first's token, manual 5.1 b).
        """
        async with self._login_lock:
            if seen is not None and self._logins != seen and self._token is not None:
                return
            self._token = None
            password = hashlib.sha512(self.config.password.encode()).hexdigest()
            params = {"username": self.config.username, "password": password}
            try:
                result = await self._send("login", params)
            except RpcError as err:
                raise login_error(err) from None
            cookie = result.get("cookie")
            if not isinstance(cookie, str) or not cookie:
                raise PlcProtocolError("the PLC accepted the login but sent no token")
            self._token = cookie
            self._logins += 1

    async def _call(self, method: str, params: Any) -> dict[str, Any]:
        """Call a method that needs a login; after a refusal log in once and retry once.

        The manual defines no session error code (its error page is missing), only that a
        request needs a login first (7.1 a, 8.1 a, 9.1 a) and that a token ends with another
        login or half an hour idle (5.1 b, 5.1 c). So what a refusal means is told by
        structure, never by its code: an empty read (8.1 d) that passes shows the session
        works; its status block tells STOP (9.1 d); get_permission (7) told whether the user
        may write. A refused write with the session working is not sent again; any other
        refusal is taken as a lost session: one fresh login, one retry. A renewal is counted
        when a call with the new token passes where the old one's was refused.
        """
        if self._token is None:
            await self._login(self._logins)  # callers at once share the one login
        seen = self._logins
        write = method == "write"
        try:
            return self._noted(await self._send(method, params))
        except RpcError as err:
            # Another caller's login since then would make the empty read pass on its token.
            if write and self._logins == seen and await self._session_works():
                raise self._write_refused(err) from None
        await self._login(seen)
        try:
            result = self._noted(await self._send(method, params))
        except RpcError as err:
            if not await self._session_works():
                raise session_error(err) from None
            if write:
                self.metrics.session_renewals += 1  # the status read passed, the old one not
                raise self._write_refused(err) from None
            raise request_error(err, write=False) from None
        self.metrics.session_renewals += 1
        return result

    def _write_refused(self, err: RpcError) -> PlcError:
        """Return the error of a write refused whole while the session works."""
        if self._mode not in (None, "RUN"):
            return stop_error(err.words)
        if not self._can_write:
            return permission_error(err)
        return request_error(err, write=True)

    async def _session_works(self) -> bool:
        """Send an empty read (manual 8.1 d): say whether it passed, and note its status."""
        try:
            self._noted(await self._send("read", []))
        except RpcError:
            return False
        return True

    def _noted(self, result: dict[str, Any]) -> dict[str, Any]:
        """Remember the operating mode a reply's status block reports (read and write replies)."""
        status = result.get("status")
        if isinstance(status, dict) and isinstance(status.get("Operating Mode"), str):
            self._mode = status["Operating Mode"].strip().upper()
        return result
