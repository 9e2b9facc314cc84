"""The PLCnext simulator's login and session commands (notes 3a, Authentication, Sessions)."""

from __future__ import annotations

import time
from typing import Any

from aiohttp import web

from .access import Access
from .parameters import Fault, number


class AccessRoutes:
    """The two login steps, the token check and the session commands of the simulator.

    Mixed into PlcnextSimulator, whose `_json` adds the fields every data answer carries.
    """

    access: Access
    auth: bool
    foreign: bool
    station_conflicts: bool  # a second session for a station with a live one: 409 (PyREST)
    session_cap: float | None  # the longest session timeout granted (s); None: as asked
    session_answer: str  # the create answer names the timeout "granted", or it is "absent"

    def _reason(self, documented: str, own: str) -> str:
        """Return a reason: the documented one, or in foreign mode the simulator's own."""
        return own if self.foreign else documented

    def _auth(self, step: str, fields: dict[str, Any]) -> web.Response:
        """The two steps of the login."""
        if step == "auth-token" and fields.get("scope") == "variables":
            answer = {"code": self.access.auth_code(), "expires_in": 600}
            if "state" in fields:
                answer["state"] = fields["state"]
            return web.json_response(answer)
        if step == "access-token":
            token = self.access.access_token(
                fields.get("code"), fields.get("username"), fields.get("password")
            )
            if token is None:
                status = 403 if self.foreign else 401
                raise Fault(status, self._reason("wrongPassword", "loginRefused"))
            roles = self.access.roles(self.access.tokens[token])
            return web.json_response(
                {"token_type": "Bearer", "access_token": token, "roles": roles}
            )
        raise Fault(400, "invalidRequest")

    def _user(self, request: web.Request) -> str | None:
        """Return the user of a protected request; refuse a missing or unknown token."""
        if not self.auth:
            return None
        user = self.access.user_of(request.headers.get("Authorization", ""))
        if user is None:
            challenge = "" if self.foreign else 'Bearer realm="pxcapi", error="invalid_token"'
            raise Fault(401, self._reason("invalidToken", "tokenExpired"), challenge)
        return user

    def _sessions(self, method: str, parts: list[str], fields: dict[str, Any]) -> web.Response:
        """Create, maintain and delete sessions."""
        if method == "POST" and not parts:
            station = str(fields.get("stationID", "")).strip()
            timeout = number(fields.get("timeout"), 3_600_000)
            if not station:
                raise Fault(400, "invalidStationID")
            live = (s for s in self.access.sessions.values() if s.station == station)
            if self.station_conflicts and any(s.alive(time.monotonic()) for s in live):
                raise Fault(409, self._reason("stationInUse", "conflict"))
            if self.session_cap is not None:
                timeout = min(timeout, self.session_cap * 1000)
            session_id = self.access.open(station, timeout)
            answer: dict[str, Any] = {"sessionID": session_id}
            if self.session_answer == "granted":
                answer["timeout"] = round(timeout)
            return self._json(answer, status=201)
        if method == "GET" and not parts:  # the report (notes 3a, Sessions)
            now = time.monotonic()
            entries = [
                {"id": key, "stationID": s.station, "timeout": round(s.timeout * 1000)}
                for key, s in self.access.sessions.items()
                if s.alive(now)
            ]
            return self._json({"sessions": entries, "next": None})
        if parts and method in ("POST", "PUT"):
            self._keep_session(parts[0])
            return self._json({"sessionID": parts[0]})
        if parts and method == "DELETE":
            self.access.sessions.pop(parts[0], None)
            return web.Response(status=204)
        raise Fault(400, "invalidRequest")

    def _keep_session(self, session_id: Any) -> None:
        """Keep a named session alive; one that is gone answers 410 (notes 3a, Sessions)."""
        if session_id and not self.access.touch(str(session_id)):
            raise Fault(410, self._reason("invalidSessionID", "sessionTimedOut"))
