"""TecoApi services over HTTP: authentication, error answers, GetObject and PutObject retries."""

from __future__ import annotations

import base64
from collections.abc import Mapping, Sequence
import json
import re
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
from .arrays import answered
from .codec import dumps
from .errors import (
    NOT_FOUND,
    TOO_MANY_ITEMS,
    TOO_MANY_REQUESTED,
    TecoError,
    blame,
    missing_variable,
    parse_error,
    refused,
    refused_value,
    request_error,
)
from .paths import SERVICE, VariablePath, get_uri, nest
from .reading import Gone, Reading, gone_for, under

AUTH_METHODS = ("digest", "basic")


_STRINGS_OR_NON_FINITE = re.compile(
    r'"(?:[^"\\]|\\.)*"|(?<![\w.])-?(?:nan|inf(?:inity)?)(?![\w.])', re.IGNORECASE
)


def loads(text: str) -> Any:
    """Parse an answer; a REAL the PLC printed as nan or inf (not JSON) becomes null.

    Real firmware prints a non-finite REAL as a bare word (reported for Foxtrot CPUs); the spec is
    silent. Only words outside strings are touched, so the one point fails alone with its own
    error (its value is missing) and no text changes.
    """
    try:
        return json.loads(text)
    except ValueError:
        fixed = _STRINGS_OR_NON_FINITE.sub(
            lambda match: match[0] if match[0].startswith('"') else "null", text
        )
        return json.loads(fixed)


def _text(raw: bytes) -> str:
    """Decode an answer: UTF-8, else the Windows-1250 a Czech PLC keeps its strings in."""
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        return raw.decode("cp1250", "replace")


def basic_authorization(user: str, password: str) -> str:
    """Return the Basic `Authorization` value (RFC 7617) for a TecoApi user.

    Latin-1 as aiohttp's BasicAuth encoded it, UTF-8 for what Latin-1 cannot hold (RFC 7617
    2.1); the TecoApi manual (3.1) names no charset.
    """
    if ":" in user:
        raise PlcAuthenticationError("a user name for Basic authentication cannot contain ':'")
    pair = f"{user}:{password}"
    try:
        raw = pair.encode("latin-1")
    except UnicodeEncodeError:
        raw = pair.encode()
    return "Basic " + base64.b64encode(raw).decode("ascii")


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
        # Names a GetObject may carry, learned from 413.002 (a CPU taking fewer than planned).
        self.max_names: int | None = None

    def _credentials(self, headers: dict[str, str]) -> dict[str, Any]:
        """Return the request arguments that authenticate: Digest (preferred) or Basic.

        Basic goes into `headers` (aiohttp deprecates its BasicAuth helper).
        """
        user, password = self._config.username, self._config.password
        if self.auth == "basic":
            headers["Authorization"] = basic_authorization(user, password)
            return {}
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
            method, path, data=body, headers=headers, encoded=True, **self._credentials(headers)
        )
        if not 200 <= status < 300:
            raise parse_error(status, raw, answer_headers.get("WWW-Authenticate", ""))
        if not raw.strip():
            return None
        try:
            return loads(_text(raw))
        except (ValueError, RecursionError):  # RecursionError: nested deeper than a stack holds
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
        self,
        groups: Sequence[Sequence[VariablePath]],
        lows: Mapping[str, tuple[int, ...]] | None = None,
    ) -> Reading:
        """Read groups of paths; return raw values and per-path errors.

        A variable found unknown is not asked again in later groups: every asked path inside it
        fails with its error. `lows` are the arrays' first indices known (arrays.answered).
        """
        reading = Reading()
        asked = [path for group in groups for path in group]
        for group in groups:
            await self._get(self._left(group, reading), reading, asked, lows)
        return reading

    @staticmethod
    def _left(pending: Sequence[VariablePath], reading: Reading) -> list[VariablePath]:
        """Return the paths not inside a variable found unknown; fail the others."""
        if not reading.gone:
            return list(pending)
        left = []
        for path in pending:
            if (gone := gone_for(path, reading.gone)) is not None:
                reading.failed[path.key] = gone.error(path)
            else:
                left.append(path)
        return left

    async def _get(
        self,
        pending: list[VariablePath],
        reading: Reading,
        asked: Sequence[VariablePath],
        lows: Mapping[str, tuple[int, ...]] | None,
    ) -> None:
        """Read one group; drop an unknown variable (400.005) and ask for the rest again.

        When the answer does not say which path it means, or the group asks too much
        (413.002/413.004), each half is read on its own.
        """
        while pending:
            try:
                answer = await self.send("GET", get_uri(path.text for path in pending))
            except TecoError as err:
                name = missing_variable(err)
                if name is None and err.code == NOT_FOUND and len(pending) == 1:
                    name = pending[0].text  # worded without the name: a lone path is the one
                hit = blame(pending, name) if name is not None else None
                if name is not None and hit is not None:
                    lost, length = hit
                    path = pending[lost[0]]
                    gone = VariablePath(path.segments[:length])
                    if len(lost) == 1 and name.strip().lower() == path.key:
                        # Named by its whole path: the PLC did not say where its walk stopped.
                        gone = await self._unknown_ancestor(path, asked) or gone
                    reading.gone[gone.key] = Gone(gone, name)
                    pending = self._left(pending, reading)
                    continue
                split = name is not None or err.code in (
                    NOT_FOUND,
                    TOO_MANY_REQUESTED,
                    TOO_MANY_ITEMS,
                )
                if err.code == TOO_MANY_REQUESTED and len(pending) > 1:
                    self.max_names = min(self.max_names or len(pending), len(pending) // 2)
                if split and len(pending) > 1:
                    half = len(pending) // 2
                    await self._get(pending[:half], reading, asked, lows)
                    await self._get(self._left(pending[half:], reading), reading, asked, lows)
                    return
                if err.code == TOO_MANY_ITEMS:
                    reading.too_big.add(pending[0].key)
                    reading.failed[pending[0].key] = PlcAddressError(
                        f"{pending[0].text} holds more items than the PLC answers at once"
                    )
                    return
                raise request_error(err, self.auth) from None
            placed = answered(answer, pending, lows, reading.lists)
            reading.answers.append((answer, pending))
            for path in pending:
                if path.key in placed:
                    reading.found[path.key] = placed[path.key]
                else:
                    reading.failed[path.key] = PlcProtocolError(
                        f"{path.text} is missing from the answer, or cannot be told apart in it"
                    )
            return

    async def exists(self, path: VariablePath) -> bool:
        """Return whether the PLC knows a path (one GetObject of it alone; 413.004 is known)."""
        try:
            await self.send("GET", get_uri([path.text]))
        except TecoError as err:
            if err.code == NOT_FOUND:
                return False
            if err.code in (TOO_MANY_REQUESTED, TOO_MANY_ITEMS):
                return True
            raise request_error(err, self.auth) from None
        return True

    async def _unknown_ancestor(
        self, path: VariablePath, asked: Sequence[VariablePath]
    ) -> VariablePath | None:
        """Return the shortest ancestor of an unknown path that others share and the PLC lacks.

        A PLC that names the whole path answers one unknown path per request: a renamed
        structure would cost a request per member. One probe per level instead, from the top,
        while another asked path lies under it (a structure too big to answer exists: 413).
        """
        for length in range(1, len(path.segments)):
            prefix = VariablePath(path.segments[:length])
            if not any(other is not path and under(other, prefix) for other in asked):
                return None
            if not await self.exists(prefix):
                return prefix
        return None

    async def put(self, pairs: Sequence[tuple[VariablePath, Any]]) -> dict[int, PlcError]:
        """Write (path, JSON value) pairs with one PutObject; return the failures by position.

        A variable the PLC refuses (400.005, 400.015) fails alone: the others are sent again.
        When the answer does not say which one it means, each half is sent on its own.
        """
        failures: dict[int, PlcError] = {}
        await self._put(pairs, list(range(len(pairs))), failures)
        return failures

    async def _put(
        self,
        pairs: Sequence[tuple[VariablePath, Any]],
        pending: list[int],
        failures: dict[int, PlcError],
    ) -> None:
        """Write the pending pairs; record the refused ones in failures."""
        while pending:
            body = dumps(nest(pairs[index] for index in pending))
            try:
                await self.send("PUT", SERVICE + "PutObject", body.encode("ascii"))
            except TecoError as err:
                if not refused(err):
                    raise request_error(err, self.auth) from None
                value, name = refused_value(err), missing_variable(err)
                target = name if name is not None else (value[1] if value else None)
                paths = [pairs[index][0] for index in pending]
                hit = blame(paths, target) if target is not None else None
                if hit is None and len(pending) == 1:
                    hit = [0], len(paths[0].segments)  # worded without the name: the lone one
                if hit is None:
                    half = len(pending) // 2
                    await self._put(pairs, pending[:half], failures)
                    await self._put(pairs, pending[half:], failures)
                    return
                for position in hit[0]:
                    failures[pending[position]] = _refusal(paths[position].text, err)
                pending = [index for index in pending if index not in failures]
                continue
            return


def _refusal(text: str, err: TecoError) -> PlcError:
    """Return the error of one path a PutObject refusal (400.005 or 400.015) concerns."""
    value, name = refused_value(err), missing_variable(err)
    if value is not None:
        return PlcValueError(
            f"{text}: the PLC did not take {value[0]} (the variable is a {value[2]}; 400.015)"
        )
    if err.code == NOT_FOUND:
        shown = f"'{name}' is not found" if name is not None else err.message.strip()[:80]
        return PlcAddressError(f"{text}: the PLC does not know this variable (400.005: {shown})")
    return PlcValueError(f"{text}: the PLC did not take the value ({err.message.strip()[:80]})")
