"""A small client of Home Assistant's HTTP and websocket APIs, standard library only.

It makes the calls the frontend makes, for scripts/demo_check.py (which runs with the machine's
own python3, outside the demo's virtual environment).
"""

from __future__ import annotations

import base64
import json
import os
import socket
import struct
from typing import Any
import urllib.error
import urllib.parse
import urllib.request

CLIENT_ID = "http://127.0.0.1/"
"""The OAuth client id the frontend would give: its own address."""


class Hass:
    """A few calls of Home Assistant's HTTP API."""

    def __init__(self, port: int) -> None:
        """Talk to the Home Assistant on this port."""
        self.port = port
        self.base = f"http://127.0.0.1:{port}"
        self.token = ""

    def call(self, method: str, path: str, body: Any = None, *, form: bool = False) -> Any:
        """Send one request; return the decoded JSON answer (or the text)."""
        headers = {"Authorization": f"Bearer {self.token}"} if self.token else {}
        data = None
        if body is not None and form:
            data = urllib.parse.urlencode(body).encode()
            headers["Content-Type"] = "application/x-www-form-urlencoded"
        elif body is not None:
            data = json.dumps(body).encode()
            headers["Content-Type"] = "application/json"
        request = urllib.request.Request(self.base + path, data, headers, method=method)
        try:
            with urllib.request.urlopen(request, timeout=30) as answer:
                text = answer.read().decode()
        except urllib.error.HTTPError as err:  # the body says why (a refused action's message)
            raise RuntimeError(f"{method} {path}: {err.code} {err.read().decode()[:300]}") from None
        try:
            return json.loads(text)
        except json.JSONDecodeError:
            return text

    def tokens(self, code: str) -> None:
        """Trade an authorization code for an access token, as the frontend does."""
        body = {"grant_type": "authorization_code", "code": code, "client_id": CLIENT_ID}
        self.token = self.call("POST", "/auth/token", body, form=True)["access_token"]


class Socket:
    """Home Assistant's websocket API over a minimal client (text frames, no extensions)."""

    def __init__(self, hass: Hass) -> None:
        """Connect and authenticate with the token the HTTP side holds."""
        self.sock = socket.create_connection(("127.0.0.1", hass.port), timeout=30)
        self.buffer = b""
        self.last_id = 0
        key = base64.b64encode(os.urandom(16)).decode()
        self.sock.sendall(
            f"GET /api/websocket HTTP/1.1\r\nHost: 127.0.0.1:{hass.port}\r\n"
            f"Upgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Key: {key}\r\n"
            "Sec-WebSocket-Version: 13\r\n\r\n".encode()
        )
        while b"\r\n\r\n" not in self.buffer:
            self.buffer += self._recv()
        head, self.buffer = self.buffer.split(b"\r\n\r\n", 1)
        if b" 101 " not in head.split(b"\r\n")[0]:
            raise ConnectionError(f"no websocket: {head[:200]!r}")
        self.receive()  # auth_required
        self.send({"type": "auth", "access_token": hass.token})
        if (answer := self.receive())["type"] != "auth_ok":
            raise ConnectionError(f"websocket authentication failed: {answer}")

    def _recv(self) -> bytes:
        """Return the next bytes from the socket; a closed socket is an error."""
        if not (chunk := self.sock.recv(65536)):
            raise ConnectionError("Home Assistant closed the websocket")
        return chunk

    def _read(self, count: int) -> bytes:
        """Return exactly count bytes."""
        while len(self.buffer) < count:
            self.buffer += self._recv()
        data, self.buffer = self.buffer[:count], self.buffer[count:]
        return data

    def _frame(self, opcode: int, payload: bytes) -> None:
        """Send one masked frame, as a client must."""
        size = len(payload)
        if size < 126:
            head = struct.pack("!BB", 0x80 | opcode, 0x80 | size)
        elif size < 65536:
            head = struct.pack("!BBH", 0x80 | opcode, 0x80 | 126, size)
        else:
            head = struct.pack("!BBQ", 0x80 | opcode, 0x80 | 127, size)
        mask = os.urandom(4)
        self.sock.sendall(head + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(payload)))

    def send(self, message: dict[str, Any]) -> None:
        """Send one JSON message."""
        self._frame(0x1, json.dumps(message).encode())

    def receive(self) -> dict[str, Any]:
        """Return the next JSON message, answering pings on the way."""
        payload = b""
        while True:
            first, second = self._read(2)
            size = second & 0x7F
            if size == 126:
                size = struct.unpack("!H", self._read(2))[0]
            elif size == 127:
                size = struct.unpack("!Q", self._read(8))[0]
            data = self._read(size)
            opcode = first & 0x0F
            if opcode == 0x8:
                raise ConnectionError("Home Assistant closed the websocket")
            if opcode == 0x9:
                self._frame(0xA, data)
            elif opcode in (0x0, 0x1):
                payload += data
                if first & 0x80:
                    return dict(json.loads(payload))

    def call(self, kind: str, **data: Any) -> Any:
        """Send one command and return its result; a refused command is an error."""
        self.last_id += 1
        self.send({"id": self.last_id, "type": kind, **data})
        while (answer := self.receive()).get("id") != self.last_id:
            pass
        if not answer.get("success"):
            raise RuntimeError(f"{kind} refused: {answer.get('error')}")
        return answer.get("result")

    def close(self) -> None:
        """Close the connection."""
        self.sock.close()
