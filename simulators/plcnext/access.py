"""Users, tokens and sessions of the PLCnext simulator (notes 3a, Authentication, Sessions)."""

from __future__ import annotations

from dataclasses import dataclass
import secrets
import time


@dataclass(slots=True)
class Session:
    """A session: its station, timeout and last use (monotonic seconds)."""

    station: str
    timeout: float
    used: float

    def alive(self, now: float) -> bool:
        """True while the session has been used within its timeout."""
        return now - self.used <= self.timeout


class Access:
    """Auth codes, access tokens and sessions; tests expire them at will."""

    def __init__(self, users: dict[str, tuple[str, list[str]]]) -> None:
        """Keep the users: name -> (password, EHmi roles)."""
        self.users = users
        self.codes: dict[str, float] = {}
        self.tokens: dict[str, str] = {}  # token -> user
        self.sessions: dict[str, Session] = {}
        self.logins = 0
        self.created = 0  # sessions made (a keep-alive or a use makes none)

    def auth_code(self) -> str:
        """Return a new auth token (valid 600 s, notes 3a)."""
        code = secrets.token_hex(8)
        self.codes[code] = time.monotonic() + 600
        return code

    def access_token(self, code: object, user: object, password: object) -> str | None:
        """Return an access token for valid credentials and a live auth code, else None."""
        expires = self.codes.pop(code, 0.0) if isinstance(code, str) else 0.0
        known = self.users.get(user) if isinstance(user, str) else None
        if expires < time.monotonic() or known is None or known[0] != password:
            return None
        token = secrets.token_hex(8)
        self.tokens[token] = str(user)
        self.logins += 1
        return token

    def user_of(self, header: str) -> str | None:
        """Return the user of an Authorization header (`Bearer t`, or the bare token)."""
        token = header.removeprefix("Bearer ").strip()
        return self.tokens.get(token)

    def roles(self, user: str | None) -> list[str]:
        """Return a user's EHmi roles."""
        return self.users[user][1] if user in self.users else []

    def expire_tokens(self) -> None:
        """Forget every access token (their lifetime ended)."""
        self.tokens.clear()

    def open(self, station: str, timeout_ms: float) -> str:
        """Create a session; return its id."""
        session_id = f"s{secrets.randbelow(10**10):010d}"
        self.sessions[session_id] = Session(station, timeout_ms / 1000, time.monotonic())
        self.created += 1
        return session_id

    def touch(self, session_id: str) -> bool:
        """Keep a session alive; False when it is unknown or timed out."""
        session = self.sessions.get(session_id)
        now = time.monotonic()
        if session is None or not session.alive(now):
            self.sessions.pop(session_id, None)
            return False
        session.used = now
        return True

    def expire_sessions(self) -> None:
        """Forget every session (timed out, or the PLC restarted)."""
        self.sessions.clear()
