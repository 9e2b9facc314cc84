"""TecoApi services over HTTP: authentication, error answers, GetObject and PutObject retries."""

from __future__ import annotations

from collections.abc import Sequence
import json
from typing import Any

import aiohttp

from ...errors import (
    PlcAddressError,
    PlcAuthenticationError,
    PlcError,
    PlcProtocolError,
    PlcValueError,
)
from ...http import HttpTransport
from ...types import ClientMetrics, ConnectionConfig
from .codec import dumps
from .errors import (
    TOO_MANY_ITEMS,
    TOO_MANY_REQUESTED,
    TecoError,
    missing_variable,
    parse_error,
    refused_value,
    request_error,
)
from .paths import SERVICE, VariablePath, find, get_uri, nest

AUTH_METHODS = ("digest", "basic")


def named(paths: Sequence[VariablePath], name: str) -> list[int]:
    """Return the positions of the paths an error names: the variable itself, or inside it."""
    wanted = name.strip().lower()
    inside = (wanted + ".", wanted + "[")
    hits = [index for index, path in enumerate(paths) if path.key == wanted]
    return hits or [index for index, path in enumerate(paths) if path.key.startswith(inside)]


def _text(raw: bytes) -> str:
    """Decode an answer: UTF-8, else the Windows-1250 a Czech PLC keeps its strings in."""
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        return raw.decode("cp1250", "replace")


class TecoApi:
    """The services of one PLC; every request goes through one HttpTransport."""

    def __init__(
        self,
        config: ConnectionConfig,
        session: aiohttp.ClientSession,
        metrics: ClientMetrics,
        request_interval: float,
    ) -> None:
        """Bind to a PLC; `options["auth"]` picks digest (default) or basic (3.1)."""
        self._config = config
        self._metrics = metrics
        self._transport = HttpTransport(config, session, metrics, request_interval=request_interval)
        self.auth = str(config.options.get("auth", "digest")).strip().lower()
        self._digest: aiohttp.DigestAuthMiddleware | None = None

    def _credentials(self) -> dict[str, Any]:
        """Return the request arguments that authenticate: Digest (preferred) or Basic."""
        user, password = self._config.username, self._config.password
        if self.auth == "basic":
            return {"auth": aiohttp.BasicAuth(user, password)}
        if self.auth != "digest":
            raise PlcAuthenticationError(
                f"unknown authentication {self.auth!r}; use {' or '.join(AUTH_METHODS)}"
            )
        if self._digest is None:
            try:
                self._digest = aiohttp.DigestAuthMiddleware(user, password)
            except ValueError as err:
                raise PlcAuthenticationError(f"the user name cannot be used: {err}") from None
        return {"middlewares": (self._digest, self._watch)}

    async def _watch(
        self, request: aiohttp.ClientRequest, handler: aiohttp.ClientHandlerType
    ) -> aiohttp.ClientResponse:
        """Count the nonce renewals (401.020 "New balls", stale=true) the digest step answers."""
        response = await handler(request)
        if response.status == 401:
            challenge = response.headers.get("WWW-Authenticate", "").replace(" ", "").lower()
            if "stale=true" in challenge or 'stale="true"' in challenge:
                self._metrics.session_renewals += 1
        return response

    async def send(self, method: str, path: str, body: bytes | None = None) -> Any:
        """Send one request; return its JSON (None when empty) or raise its TecoError."""
        headers = {"Accept": "application/json"}
        if body is not None:
            headers["Content-Type"] = "application/json"
        status, answer_headers, raw = await self._transport.request(
            method, path, data=body, headers=headers, encoded=True, **self._credentials()
        )
        if not 200 <= status < 300:
            raise parse_error(status, raw, answer_headers.get("WWW-Authenticate", ""))
        if not raw.strip():
            return None
        try:
            return json.loads(_text(raw))
        except ValueError:
            raise PlcProtocolError(
                f"the PLC answered {path[:40]} with something other than JSON"
            ) from None

    async def ask(self, method: str, path: str) -> Any:
        """Send one request whose every error fails it as a whole."""
        try:
            return await self.send(method, path)
        except TecoError as err:
            raise request_error(err, self.auth) from None

    async def get(
        self, groups: Sequence[Sequence[VariablePath]]
    ) -> tuple[dict[str, Any], dict[str, PlcError]]:
        """Read groups of paths; return raw values and per-path errors, by path key."""
        found: dict[str, Any] = {}
        failed: dict[str, PlcError] = {}
        for group in groups:
            await self._get(list(group), found, failed)
        return found, failed

    async def _get(
        self, pending: list[VariablePath], found: dict[str, Any], failed: dict[str, PlcError]
    ) -> None:
        """Read one group; drop an unknown variable (400.005) and ask for the rest again."""
        while pending:
            try:
                answer = await self.send("GET", get_uri(path.text for path in pending))
            except TecoError as err:
                if (name := missing_variable(err)) is not None:
                    lost = named(pending, name) or range(len(pending))
                    for index in lost:
                        failed[pending[index].key] = PlcAddressError(
                            f"{pending[index].text}: the PLC has no public variable {name} "
                            "(400.005)"
                        )
                    pending = [path for index, path in enumerate(pending) if index not in lost]
                    continue
                if err.code in (TOO_MANY_REQUESTED, TOO_MANY_ITEMS) and len(pending) > 1:
                    half = len(pending) // 2
                    await self._get(pending[:half], found, failed)
                    await self._get(pending[half:], found, failed)
                    return
                if err.code == TOO_MANY_ITEMS:
                    failed[pending[0].key] = PlcAddressError(
                        f"{pending[0].text} holds more items than the PLC answers at once"
                    )
                    return
                raise request_error(err, self.auth) from None
            for path in pending:
                try:
                    found[path.key] = find(answer, path)
                except KeyError:
                    failed[path.key] = PlcProtocolError(f"{path.text} is missing from the answer")
            return

    async def put(self, pairs: Sequence[tuple[VariablePath, Any]]) -> dict[int, PlcError]:
        """Write (path, JSON value) pairs with one PutObject; return the failures by position.

        A variable the PLC refuses (400.005, 400.015) fails alone: the others are sent again.
        """
        failures: dict[int, PlcError] = {}
        pending = list(range(len(pairs)))
        while pending:
            body = dumps(nest(pairs[index] for index in pending))
            try:
                await self.send("PUT", SERVICE + "PutObject", body.encode("ascii"))
            except TecoError as err:
                refused, name = refused_value(err), missing_variable(err)
                target = name if name is not None else (refused[1] if refused else None)
                lost = named([pairs[i][0] for i in pending], target) if target else []
                if not lost:
                    raise request_error(err, self.auth) from None
                for position in lost:
                    text = pairs[pending[position]][0].text
                    failures[pending[position]] = (
                        PlcValueError(
                            f"{text}: the PLC did not take {refused[0]} "
                            f"(the variable is a {refused[2]}; 400.015)"
                        )
                        if refused is not None
                        else PlcAddressError(
                            f"{text}: the PLC has no public variable {name} (400.005)"
                        )
                    )
                pending = [index for position, index in enumerate(pending) if position not in lost]
                continue
            return failures
        return failures
