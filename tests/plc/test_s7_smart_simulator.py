"""The S7-200 SMART simulator speaks the manual's protocol (raw JSON-RPC, no client)."""

from __future__ import annotations

from collections.abc import AsyncGenerator
from datetime import datetime
import hashlib
import json
from typing import Any

import aiohttp
import pytest

from simulators.s7_smart import (
    DEFAULT_PASSWORD,
    DEFAULT_USER,
    ERRORS,
    HttpFault,
    S7SmartSimulator,
)
from simulators.s7_smart.errors import INVALID_PARAMS, SHUFFLED

pytestmark = pytest.mark.no_pacing

type Reply = dict[str, Any]


class Raw:
    """Posts hand-made JSON-RPC bodies to the simulator."""

    def __init__(self, sim: S7SmartSimulator, session: aiohttp.ClientSession) -> None:
        self.url = f"https://{sim.host}:{sim.port}/Web_api"
        self.session = session
        self.cookie = ""

    async def post(self, body: Any, content_type: str = "application/json") -> Reply:
        data = body if isinstance(body, bytes) else json.dumps(body).encode()
        headers = {"Content-Type": content_type, "Cookie": self.cookie}
        async with self.session.post(self.url, data=data, headers=headers, ssl=False) as reply:
            assert reply.status == 200
            result: Reply = await reply.json()
            return result

    async def call(self, method: str, params: Any = None, call_id: Any = 7) -> Reply:
        return await self.post(
            {"jsonrpc": "2.0", "method": method, "id": call_id, "params": params}
        )

    async def login(self, user: str = DEFAULT_USER, password: str = DEFAULT_PASSWORD) -> Reply:
        digest = hashlib.sha512(password.encode()).hexdigest()
        reply = await self.call("login", {"username": user, "password": digest})
        self.cookie = reply.get("result", {}).get("cookie", "")
        return reply


@pytest.fixture
async def raw(s7_smart_sim: S7SmartSimulator) -> AsyncGenerator[Raw]:
    async with aiohttp.ClientSession() as session:
        yield Raw(s7_smart_sim, session)


def code(reply: Reply) -> int:
    error: int = reply["error"]["code"]
    assert reply["error"]["message"] == ERRORS[error]
    return error


async def test_envelope(raw: Raw, s7_smart_sim: S7SmartSimulator) -> None:
    browse = await raw.call("browse", call_id="abc")
    assert browse["id"] == "abc"
    assert browse["result"]["version"] == "1.0.0"
    assert "write" in browse["result"]["api"]
    assert code(await raw.post({"jsonrpc": "2.0", "method": "browse", "id": 1}, "text/plain")) == (
        -32600
    )
    batch = await raw.post([{"jsonrpc": "2.0", "method": "browse", "id": 1}])
    assert (code(batch), batch["id"]) == (-32600, None)
    assert code(await raw.post(b"{nope")) == -32700
    assert code(await raw.post(b"\xff")) == -32700
    assert code(await raw.post({"jsonrpc": "1.0", "method": "browse", "id": 1})) == -32600
    assert code(await raw.post({"jsonrpc": "2.0", "method": "browse"})) == -32600
    assert code(await raw.call("reboot")) == -32601
    assert code(await raw.post(b" " * (15 * 1024 + 1))) == 2003
    assert s7_smart_sim.calls["browse"] == 1
    async with raw.session.get(raw.url, ssl=False) as reply:
        assert reply.status == 405


async def test_login_and_tokens(raw: Raw) -> None:
    assert code(await raw.call("read", [])) == 1002
    assert code(await raw.call("login", None)) == -32602
    assert code(await raw.call("login", {"username": "admin"})) == -32602
    assert code(await raw.login(password="wrong")) == 1001
    first = (await raw.login())["result"]["cookie"]
    assert first.startswith("Session-Id=")
    assert (await raw.call("get_permission"))["result"]["permission"] == {"write": True}
    await raw.login()
    raw.cookie = first  # the newer login of the same user replaced this token
    assert code(await raw.call("read", [])) == 1002
    assert (await raw.call("logout"))["result"]["code"] == 0  # not online: still a success
    await raw.login()
    assert (await raw.call("logout"))["result"]["message"] == "Success."
    assert code(await raw.call("read", [])) == 1002


async def test_read_nodes(raw: Raw, s7_smart_sim: S7SmartSimulator) -> None:
    await raw.login()
    s7_smart_sim.set("VB1000", "s7-200 smart web api.", "string")
    s7_smart_sim.set("VB2000", 255, "unsigned")
    s7_smart_sim.set("VB2001", 255, "unsigned")  # a length byte past 254 reads 254 characters
    nodes = [
        {"var": "vb1000", "mode": "String"},
        {"type": "address", "var": "VB2000"},
        {"var": "VB70000"},
        {"var": "VW0", "mode": "float"},
        {"var": "HC0", "mode": "float"},
        {"var": "T0", "mode": "string"},
        {"var": "VB0", "mode": 5},
        {"var": "V0.8"},
        {"var": "AIW3"},
        {"var": "T256"},
        {"var": 12},
        {"type": "symbol", "var": "VB0"},
        "VB0",
        {"var": "VB2001", "mode": "string"},
        {"var": "XB0"},
    ]
    reply = (await raw.call("read", nodes))["result"]
    assert reply["status"]["Operating Mode"] == "RUN"
    data = reply["data"]
    assert data[0] == {
        "code": 0,
        "message": "Success.",
        "var": "vb1000",
        "value": "s7-200 smart web api.",
    }
    assert data[1]["value"] == -1
    assert [node["code"] for node in data[2:]] == [
        3004, 3005, 3005, 3005, 3005, 3004, 3004, 3004, 3004, -32602, -32602, 0, 3004,
    ]  # fmt: skip
    assert len(data[-2]["value"]) == 254


async def test_limits(raw: Raw) -> None:
    await raw.login()
    assert code(await raw.call("read", [{"var": "VB0"}] * 33)) == 2002
    assert code(await raw.call("read", {"var": "VB0"})) == -32602
    assert (await raw.call("read", None))["result"]["data"] == []


async def test_write_nodes(raw: Raw, s7_smart_sim: S7SmartSimulator) -> None:
    await raw.login()
    nodes: list[Any] = [
        {"var": "VB0", "value": 300},
        {"var": "VB0", "value": True},
        {"var": "VW0", "value": 1.5},
        {"var": "VW0", "value": "1"},
        {"var": "VD0", "mode": "float", "value": float("nan")},
        {"var": "VD0", "mode": "float", "value": 1e39},
        {"var": "VW0", "mode": "raw", "value": [1]},
        {"var": "VW0", "mode": "raw", "value": [1, 256]},
        {"var": "VW0", "mode": "raw", "value": [1, True]},
        {"var": "VB0", "mode": "string", "value": "x" * 255},
        {"var": "VB20479", "mode": "string", "value": "x"},
        {"var": "VB0", "mode": "string", "value": 5},
        {"var": "V0.0", "value": 2},
        {"var": "V0.0", "value": 1.0},
        {"var": "DATE", "value": "2024-13-01 00:00:00"},
        {"var": "DATE", "value": "1999-12-31 23:59:59"},
        {"var": "VB0"},
        {"var": "SMB29", "value": 1},
        {"var": "SM0.0", "value": 1},
        {"var": "VW0", "mode": "unsigned", "value": 65535},
        {"var": "V2.0", "value": True},
        {"var": "DATE", "mode": "raw", "value": "2024-01-02 03:04:05"},
    ]
    data = (await raw.call("write", nodes))["result"]["data"]
    assert [node["code"] for node in data] == [3006] * 17 + [3007, 3007, 0, 0, 0]
    assert all("value" not in node for node in data)
    assert s7_smart_sim.get("VW0") == -1
    assert s7_smart_sim.get("V2.0") is True
    assert s7_smart_sim.clock == datetime(2024, 1, 2, 3, 4, 5)


async def test_write_refusals(raw: Raw, s7_smart_sim: S7SmartSimulator) -> None:
    await raw.login()
    s7_smart_sim.mode = "STOP"
    assert code(await raw.call("write", [{"var": "VB0", "value": 1}])) == 2001
    assert (await raw.call("write", []))["result"]["status"]["Operating Mode"] == "STOP"
    s7_smart_sim.write_permission = False
    assert code(await raw.call("write", [])) == 1003
    assert (await raw.call("get_permission"))["result"]["permission"] == {"write": False}


async def test_reading_switches(raw: Raw, s7_smart_sim: S7SmartSimulator) -> None:
    """Each switch of READINGS.md changes what it names only."""
    await raw.login()
    write = [{"var": "VW0", "value": 1}]
    s7_smart_sim.mode, s7_smart_sim.stop_refusal = "STOP", "node"
    reply = await raw.call("write", write)
    assert reply["result"]["status"]["Operating Mode"] == "STOP"
    assert reply["result"]["data"] == [{"code": 2001, "message": "CPU not in RUN.", "var": "VW0"}]
    s7_smart_sim.codes = "shuffled"
    reply = await raw.call("write", write)
    assert reply["result"]["data"][0]["message"] == "CPU is not in RUN mode"
    s7_smart_sim.max_nodes, s7_smart_sim.node_limit_error = 2, INVALID_PARAMS
    assert (await raw.call("read", [{"var": "VW0"}] * 3))["error"]["code"] == INVALID_PARAMS
    s7_smart_sim.node_limit_error = 2002
    assert (await raw.call("read", [{"var": "VW0"}] * 3))["error"] == {
        "code": SHUFFLED[2002][0],
        "message": "Too many nodes.",
    }
    s7_smart_sim.codes = "foreign"
    assert (await raw.call("read", [{"var": "VW0"}] * 3))["error"]["code"] > 7000
    assert (await raw.call("read", [{"var": "VW0"}] * 2))["result"]["data"][0]["code"] == 0


async def test_http_switches(raw: Raw, s7_smart_sim: S7SmartSimulator) -> None:
    """`error_status` sets the HTTP status of error replies; `http_faults` answer in their place."""
    s7_smart_sim.error_status = 500
    body = json.dumps({"jsonrpc": "2.0", "method": "read", "id": 1, "params": []})
    headers = {"Content-Type": "application/json"}
    async with raw.session.post(raw.url, data=body, headers=headers, ssl=False) as reply:
        assert reply.status == 500
        assert (await reply.json())["error"]["message"] == "Invalid token."
    s7_smart_sim.http_faults = [HttpFault(429, "slow down", {"Retry-After": "3"})]
    async with raw.session.post(raw.url, data=body, headers=headers, ssl=False) as reply:
        assert (reply.status, reply.headers["Retry-After"]) == (429, "3")
        assert await reply.text() == "slow down"
    assert s7_smart_sim.http_faults == []
    assert s7_smart_sim.calls["read"] == 1  # a fault is answered before the call is handled


def test_users_and_direct_access() -> None:
    with pytest.raises(ValueError, match="at most 4"):
        S7SmartSimulator({f"user{i}": "pw" for i in range(5)})
    sim = S7SmartSimulator({"a": "1", "b": "2"})
    assert sim.v_size == 20480
    sim.set("DATE", datetime(2024, 1, 2, 3, 4, 5, 600))
    assert sim.get("date") == datetime(2024, 1, 2, 3, 4, 5)
    sim.set("SMB0", 7, "unsigned")  # tests may set what clients cannot write
    assert sim.get("smb0", "unsigned") == 7
    sim.set("VD0", 0.1, "float")
    assert sim.get("VD0", "float") == 0.1
    with pytest.raises(ValueError, match=r"VB99999: Invalid address\."):
        sim.get("VB99999")
    with pytest.raises(ValueError, match=r"VB0: Invalid value\."):
        sim.set("VB0", 1000)
