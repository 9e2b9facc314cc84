"""TecoApi authentication (3.1): Basic, or Digest (RFC 2617) with qop auth/auth-int and opaque."""

from __future__ import annotations

import base64
import binascii
from collections import Counter
import hashlib
import re
import secrets

from aiohttp import web

from .values import Fault

REALM = "TecoApi"
MAX_NONCES = 16  # nonces of recent challenges stay valid, one per client
_PAIR = re.compile(r'(\w+)\s*=\s*(?:"((?:[^"\\]|\\.)*)"|([^\s,]+))')


def _md5(*parts: str) -> str:
    """Return the hex MD5 of parts joined by colons."""
    return hashlib.md5(":".join(parts).encode(), usedforsecurity=False).hexdigest()


class Authenticator:
    """Checks each request's credentials for one method: "digest" or "basic".

    A request in the other method (or any other) is answered 403.022, so tests see which one
    a client used. Every digest challenge gives a new nonce; nonces last until `stale_nonce`
    (or a replayed nonce count) ends them, answered with 401.020 "New balls" and stale=true.
    """

    def __init__(self, method: str, users: dict[str, str]) -> None:
        if method not in ("digest", "basic"):
            raise ValueError("auth is 'digest' or 'basic'")
        self.method = method
        self.users = users
        self.opaque = secrets.token_hex(12)
        self.renew_next = 0  # how many digest requests in a row meet a renewed nonce
        self._nonces: dict[str, int] = {}  # each challenge's nonce -> the highest count seen
        self.accepted: Counter[str] = Counter()  # "basic", "digest auth", "digest auth-int"

    def stale_nonce(self, times: int = 1) -> None:
        """Make the next `times` digest requests meet a renewed nonce (401.020, stale=true)."""
        self.renew_next = times

    def challenge(self, *, stale: bool = False) -> str:
        """Return the WWW-Authenticate header of a 401 answer, with a nonce of its own."""
        if self.method == "basic":
            return f'Basic realm="{REALM}"'
        nonce = secrets.token_hex(12)
        self._nonces[nonce] = 0
        while len(self._nonces) > MAX_NONCES:
            del self._nonces[next(iter(self._nonces))]
        header = f'Digest realm="{REALM}",qop="auth,auth-int",nonce="{nonce}",'
        header += f'opaque="{self.opaque}"'
        return header + (",stale=true" if stale else "")

    def check(self, request: web.Request, body: bytes) -> Fault | None:
        """Return the error answer for the request's credentials, or None when they are good."""
        header = request.headers.get("Authorization", "")
        if not header:
            return Fault("401.023", "Authentication Requested")
        scheme, _, credentials = header.partition(" ")
        if scheme.lower() != self.method:
            return Fault("403.022", "Unsupported authentication method")
        if self.method == "basic":
            return self._basic(credentials)
        return self._digest(request, credentials.strip(), body)

    def _basic(self, credentials: str) -> Fault | None:
        """Check user:password in base64."""
        try:
            user, _, password = base64.b64decode(credentials, validate=True).decode().partition(":")
        except (binascii.Error, UnicodeDecodeError):
            return Fault("401.021", "Unknown name or password")
        if self.users.get(user) != password:
            return Fault("401.021", "Unknown name or password")
        self.accepted["basic"] += 1
        return None

    def _digest(self, request: web.Request, credentials: str, body: bytes) -> Fault | None:
        """Check a digest response against the nonce of one of the recent challenges."""
        fields = {key: quoted or bare for key, quoted, bare in _PAIR.findall(credentials)}
        user, qop = fields.get("username", ""), fields.get("qop", "")
        nc = fields.get("nc", "")
        count = int(nc, 16) if re.fullmatch(r"[0-9a-fA-F]{1,8}", nc) else 0
        nonce = fields.get("nonce", "")
        if self.renew_next:
            self.renew_next -= 1
            self._nonces.clear()
        if nonce not in self._nonces or (qop and count <= self._nonces[nonce]):
            self._nonces.pop(nonce, None)
            return Fault("401.020", "New balls")
        uri = fields.get("uri", "")
        if (
            user not in self.users
            or fields.get("realm") != REALM
            or fields.get("opaque") != self.opaque
            or uri not in (request.raw_path, request.path_qs)
            or qop not in ("", "auth", "auth-int")
        ):
            return Fault("401.021", "Unknown name or password")
        ha1 = _md5(user, REALM, self.users[user])
        ha2 = _md5(request.method, uri)
        if qop == "auth-int":
            ha2 = _md5(request.method, uri, hashlib.md5(body, usedforsecurity=False).hexdigest())
        if qop:
            expected = _md5(ha1, nonce, nc, fields.get("cnonce", ""), qop, ha2)
        else:
            expected = _md5(ha1, nonce, ha2)
        if not secrets.compare_digest(expected, fields.get("response", "")):
            return Fault("401.021", "Unknown name or password")
        if qop:
            self._nonces[nonce] = count
        self.accepted[f"digest {qop or 'without qop'}"] += 1
        return None
