"""The PLCnext REST data interface over HTTPS: version pin, access token, session, one send."""

from __future__ import annotations

import asyncio
from collections.abc import Callable
import contextlib
import json
import logging
import re
import secrets
import time
from typing import Any
from urllib.parse import urlencode

import aiohttp

from ...errors import PlcAuthenticationError, PlcError, PlcProtocolError
from ...http import HttpTransport
from ...types import ClientMetrics, ConnectionConfig
from .errors import ApiError, parse_error, request_error

ROOT = "/_pxc_api"
LATEST = f"{ROOT}/api"
_VERSION = re.compile(r"v?(\d+)\.(\d+)", re.ASCII)
SESSION_MIN = 300.0  # seconds: a session outlives several polls and a slow write action
KEEPALIVE_FLOOR = 0.2
"""The shortest wait between two keep-alives (seconds), whatever the PLC grants."""

_LOGGER = logging.getLogger(__name__)
SECRETS = ("code",)
"""The auth-token's field (notes 3a, Authentication), masked in the debug log with the rest."""

type Request = tuple[str, bytes | None, str | None]
"""A request made for the current session id: path with query, body, content type."""


def pinned_base(description: Any) -> str:
    """Return the versioned base path a service description names (`/_pxc_api/v1.2`).

    Phoenix Contact recommends the version used in development over `api` (latest); the
    description gives `version` ("v1.2") or `apiVersion` ("1.8.0.0"), PyREST checks both.
    """
    if isinstance(description, dict):
        for key in ("version", "apiVersion"):
            value = description.get(key)
            match = _VERSION.match(value.strip()) if isinstance(value, str) else None
            if match:
                return f"{ROOT}/v{match[1]}.{match[2]}"
    return LATEST


def loads(raw: bytes, what: str) -> Any:
    """Parse a JSON answer (None when empty); raise PlcProtocolError for anything else."""
    if not raw.strip():
        return None
    try:
        return json.loads(raw)
    except (ValueError, RecursionError):  # RecursionError: nested deeper than Python parses
        raise PlcProtocolError(f"the PLC answered {what} with something other than JSON") from None


class PlcnextApi:
    """One PLC's REST interface: every request goes through one HttpTransport."""

    def __init__(
        self, config: ConnectionConfig, session: aiohttp.ClientSession, metrics: ClientMetrics
    ) -> None:
        """Bind to a PLC; the version, token and session come with `describe` and use."""
        self._config = config
        self._metrics = metrics
        self._transport = HttpTransport(config, session, metrics, secrets=SECRETS)
        # A session lasts four poll intervals (at least SESSION_MIN), re-created ones too.
        self.session_timeout = max(4 * config.poll_interval, SESSION_MIN)
        self.base = LATEST
        self.auth_required: bool | None = None  # None: the PLC has not said yet
        self._token: str | None = None
        self._logins = 0
        self._login_lock = asyncio.Lock()
        self.session_id: str | None = None
        self.last_status = 0  # of the last data answer: 201 where a register made a group
        self._sessions = 0
        self._session_lock = asyncio.Lock()
        self.granted = self.session_timeout  # seconds the PLC keeps an unused session
        self._used = 0.0  # when a request last carried the session id (monotonic)
        self._keepalive: asyncio.Task[None] | None = None
        self.station = secrets.randbelow(2**31 - 1) + 1
        self.roles: list[str] = []

    @property
    def can_login(self) -> bool:
        """True when the settings hold a user to log in with."""
        return bool(self._config.username)

    async def send(
        self,
        method: str,
        path: str,
        body: bytes | None = None,
        content: str | None = None,
        *,
        idempotent: bool = False,
    ) -> tuple[int, Any, bytes]:
        """Send one request with the access token, if there is one; return status and answer."""
        headers = {"Accept": "application/json"}
        if content is not None:
            headers["Content-Type"] = content
        if self._token is not None:
            headers["Authorization"] = f"Bearer {self._token}"
        status, answer_headers, raw = await self._transport.request(
            method, path, data=body, headers=headers, encoded=True, idempotent=idempotent
        )
        return status, answer_headers, raw

    async def describe(self) -> Any:
        """Ask the service description and pin the API version it names."""
        status, headers, raw = await self.send("GET", LATEST)
        if not 200 <= status < 300:
            raise request_error(parse_error(status, raw, headers.get("WWW-Authenticate", "")))
        description = loads(raw, "the service description")
        self.base = pinned_base(description)
        self.note(description)
        return description

    def note(self, answer: Any) -> None:
        """Remember whether the PLC says it needs a user (every data answer says so)."""
        if isinstance(answer, dict) and isinstance(answer.get("userAuthenticationRequired"), bool):
            self.auth_required = answer["userAuthenticationRequired"]

    async def call(
        self, method: str, make: Callable[[str | None], Request], *, idempotent: bool = False
    ) -> Any:
        """Send a data request made for the current session; return its JSON answer.

        A refused token (401) and a gone session (410) are renewed once each; any other
        failure is raised as the answer's ApiError.
        """
        renewed_token = renewed_session = False
        while True:
            if self.auth_required and self._token is None and self.can_login:
                await self.login(self._logins)
            logins, sessions, session = self._logins, self._sessions, self.session_id
            path, body, content = make(session)
            status, headers, raw = await self.send(
                method, path, body, content, idempotent=idempotent
            )
            if session is not None and 200 <= status < 300 and _carries(session, path, body):
                self._used = time.monotonic()
            if 200 <= status < 300:
                answer = loads(raw, path.partition("?")[0][-40:])
                if not (isinstance(answer, dict) and "error" in answer):
                    self.note(answer)
                    self.last_status = status
                    return answer
                # A dictionary refused for rights may come as 200 with an error object.
                status = 401 if self._token is None else 403
            error = parse_error(status, raw, headers.get("WWW-Authenticate", ""))
            if status == 401 and not renewed_token and self.can_login:
                renewed_token = True
                if self._token is not None:
                    self._metrics.session_renewals += 1
                self.auth_required = True
                await self.login(logins)
                continue
            if status == 410 and not renewed_session and session is not None:
                renewed_session = True
                self._metrics.session_renewals += 1
                await self.open_session(sessions)
                continue
            if status == 401 and not self.can_login:
                raise PlcAuthenticationError(
                    f"the PLC asks for a user: enter a PLCnext user and password ({error.words})"
                )
            raise error

    async def login(self, seen: int | None = None) -> None:
        """Get an auth token, then an access token for the user (notes 3a, Authentication).

        Single-flight: a caller that saw `seen` logins before its request was refused logs in
        only if nobody has since; concurrent callers share the one new token.
        """
        async with self._login_lock:
            if seen is not None and self._logins != seen and self._token is not None:
                return
            self._token = None
            state = secrets.token_hex(8)
            answer = await self._auth("auth-token", {"scope": "variables", "state": state})
            code = answer.get("code") if isinstance(answer, dict) else None
            if not isinstance(code, str) or not code:
                raise PlcProtocolError("the PLC sent no auth token")
            answer = await self._auth(
                "access-token",
                {
                    "code": code,
                    "grant_type": "authorization_code",
                    "username": self._config.username,
                    "password": self._config.password,
                },
            )
            token = answer.get("access_token") if isinstance(answer, dict) else None
            if not isinstance(token, str) or not token:
                raise PlcProtocolError("the PLC accepted the user but sent no access token")
            roles = answer.get("roles")
            self.roles = [str(role) for role in roles] if isinstance(roles, list) else []
            self._token = token
            self._logins += 1

    async def _auth(self, step: str, body: dict[str, str]) -> Any:
        """Send one step of the login; any refusal of the user is an authentication error."""
        status, headers, raw = await self.send(
            "POST", f"{self.base}/auth/{step}", json.dumps(body).encode(), "application/json"
        )
        if 200 <= status < 300:
            return loads(raw, step)
        error = parse_error(status, raw, headers.get("WWW-Authenticate", ""))
        if status in (400, 401, 403):
            raise PlcAuthenticationError(f"the PLC refused the user or password ({error.words})")
        raise request_error(error)

    async def open_session(self, seen: int | None = None) -> None:
        """Create a session (form body `stationID=…&timeout=…`); once, for concurrent callers.

        Single-flight: a caller whose request met a gone session (`seen` sessions made before
        it) makes one only if nobody has since. The old id stays until the new one exists, so
        calls that overlap the renewal still know they had a session and wait for the new one.
        Sessions are optional (notes 3a, Sessions): a PLC that refuses one is used without.
        """
        async with self._session_lock:
            if seen is not None and self._sessions != seen and self.session_id is not None:
                return
            millis = round(self.session_timeout * 1000)
            for _attempt in range(2):
                body = urlencode({"stationID": self.station, "timeout": millis}).encode()
                try:
                    answer = await self.call("POST", self._session_request(body))
                except ApiError as err:
                    if err.status == 409:  # this station has one: another station id, once
                        self.station = secrets.randbelow(2**31 - 1) + 1
                        continue
                    if err.status in (401, 403):
                        raise request_error(err) from None
                    self.session_id = None
                    return
                found = answer.get("sessionID") if isinstance(answer, dict) else None
                self.session_id = found if isinstance(found, str) and found else None
                self._sessions += 1
                self._used = time.monotonic()
                if self.session_id is not None:
                    await self._keep(answer)
                return
            self.session_id = None

    async def _keep(self, answer: Any) -> None:
        """Take the timeout the PLC grants; keep the session alive where polls would not.

        The create answer's `timeout` (ms, as asked), else the sessions report's entry for it
        (notes 3a, Sessions: `timeout`); a PLC that names none is taken to grant what was
        asked. Anything but a positive number is no answer; more than asked is not trusted.
        """
        granted = _millis(answer)
        if granted is None:
            granted = await self._reported()
        self.granted = (
            self.session_timeout if granted is None else min(granted / 1000, self.session_timeout)
        )
        if self.granted < 2 * self._config.poll_interval and self._keepalive is None:
            self._keepalive = asyncio.create_task(self._keep_alive())

    async def _reported(self) -> float | None:
        """Return the timeout (ms) the sessions report gives this session, None if none.

        Sent as is (never renewed: the session lock is held while a session is made).
        """
        status, _headers, raw = await self.send("GET", f"{self.base}/sessions")
        try:
            answer = loads(raw, "the sessions report") if 200 <= status < 300 else None
        except PlcProtocolError:
            return None
        entries = answer.get("sessions") if isinstance(answer, dict) else None
        for entry in entries if isinstance(entries, list) else ():
            if isinstance(entry, dict) and entry.get("id") == self.session_id:
                return _millis(entry)
        return None

    async def _keep_alive(self) -> None:
        """Maintain the session when half its granted timeout passed unused (notes 3a)."""
        try:
            while (session := self.session_id) is not None:
                left = self._used + self.granted / 2 - time.monotonic()
                if left > 0:
                    await asyncio.sleep(max(left, KEEPALIVE_FLOOR))
                    continue
                status, _headers, _raw = await self.send("POST", f"{self.base}/sessions/{session}")
                if not 200 <= status < 300:
                    return  # gone (410): the next call makes one again
                self._used = max(self._used, time.monotonic())
                await asyncio.sleep(KEEPALIVE_FLOOR)
        except PlcError as err:
            _LOGGER.debug("Keeping the PLCnext session alive failed: %s", err)
        finally:
            self._keepalive = None

    def _session_request(self, body: bytes) -> Callable[[str | None], Request]:
        """Return the request maker of a session's creation."""
        form = "application/x-www-form-urlencoded"
        return lambda _session: (f"{self.base}/sessions", body, form)

    async def stop_keepalive(self) -> None:
        """Stop keeping the session alive (at close)."""
        if self._keepalive is not None:
            task, self._keepalive = self._keepalive, None
            task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await task

    async def close_session(self) -> None:
        """Stop keeping the session alive and delete it (best effort: it times out on its own)."""
        await self.stop_keepalive()
        if self.session_id is not None:
            session, self.session_id = self.session_id, None
            await self.send("DELETE", f"{self.base}/sessions/{session}")


def _carries(session: str, path: str, body: bytes | None) -> bool:
    """True when a request names the session id (and so keeps the session alive)."""
    return session in path or (body is not None and session.encode() in body)


def _millis(answer: Any) -> float | None:
    """Return a positive `timeout` (ms, a number or its text) of an answer; None otherwise."""
    raw = answer.get("timeout") if isinstance(answer, dict) else None
    if isinstance(raw, bool) or not isinstance(raw, int | float | str):
        return None
    try:
        value = float(raw)
    except ValueError:
        return None
    return value if 0 < value < float("inf") else None
