"""The PLCnext client on answers off the happy path, in both error modes: statuses, fallbacks."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from aiohttp import web
import pytest

from custom_components.plc_bridge.plc import (
    PlcAddressError,
    PlcAuthenticationError,
    PlcConnectionError,
    PlcProtocolError,
    PlcTimeoutError,
    PlcWriteRefusedError,
    Point,
)
from custom_components.plc_bridge.plc.vendors.plcnext import PlcnextClient
from simulators.plcnext import NO_ROLE_USER, PlcnextSimulator
from simulators.plcnext.demo import default_program
from simulators.plcnext.parameters import Fault

if TYPE_CHECKING:
    from .plcnext_fixtures import ConfigFactory

TEMPERATURE = Point("MainInstance.Temperature", "REAL")
PUMP = Point("MainInstance.Pump", "BOOL")
SPEED = Point("MainInstance.Speed", "INT")
GONE = Point("MainInstance.Gone", "INT")


def refuse_groups(sim: PlcnextSimulator, monkeypatch: pytest.MonkeyPatch, status: int) -> None:
    """Have the simulator answer every group command with this status."""

    def refused(*_args: Any) -> Any:
        raise Fault(status, "busy")

    monkeypatch.setattr(sim, "_groups", refused)


@pytest.mark.parametrize(
    ("status", "error"),
    [
        (408, PlcTimeoutError),
        (500, PlcConnectionError),
        (503, PlcConnectionError),
        (409, PlcProtocolError),
    ],
)
async def test_poll_failures_by_status(
    plcnext_sim: PlcnextSimulator,
    plcnext_client: PlcnextClient,
    monkeypatch: pytest.MonkeyPatch,
    status: int,
    error: type[Exception],
) -> None:
    """A failed group command fails the poll by its status, with the status in the message."""
    await plcnext_client.read([TEMPERATURE])
    refuse_groups(plcnext_sim, monkeypatch, status)
    with pytest.raises(error, match=f"HTTP {status}"):
        await plcnext_client.read([TEMPERATURE])


async def test_user_without_a_role(plcnext_config: ConfigFactory) -> None:
    """A user the PLC knows but gave no EHmi role: reads and browsing are authentication errors."""
    client = PlcnextClient(plcnext_config(username=NO_ROLE_USER))
    try:
        await client.connect()
        with pytest.raises(PlcAuthenticationError, match="EHmi role"):
            await client.read([TEMPERATURE])
        with pytest.raises(PlcAuthenticationError):
            await client.browse()
    finally:
        await client.close()


async def test_without_groups_reads_variables(
    plcnext_config: ConfigFactory, plcnext_sim: PlcnextSimulator
) -> None:
    """An interface without groups: a short list by GET, a long one by POST; unknown fail alone."""
    plcnext_sim.groups_served = False
    plcnext_sim.program = default_program(bench=300)  # Bench.Value<i> holds i
    client = PlcnextClient(plcnext_config(options={}))
    try:
        await client.connect()
        result = await client.read([TEMPERATURE, GONE])
        assert result.values[TEMPERATURE].value == 21.5
        assert isinstance(result.values[GONE].error, PlcAddressError)
        assert plcnext_sim.calls["GET variables"] >= 1
        many = [Point(f"Bench.Value{index}", "DINT") for index in range(300)]
        result = await client.read(many)
        assert [result.values[point].value for point in many] == list(range(300))
        assert plcnext_sim.calls["POST variables"] == 1
        await client.read(many)
        assert client.metrics.last_poll_requests == 1
    finally:
        await client.close()


async def test_group_of_another_id(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient, monkeypatch: pytest.MonkeyPatch
) -> None:
    """An answer for another group than the one asked is a protocol error, never shown values."""
    await plcnext_client.read([TEMPERATURE])
    original = plcnext_sim._json

    def other_id(data: dict[str, Any], status: int = 200, **headers: str) -> Any:
        if "id" in data and "variables" in data and status == 200:
            data = {**data, "id": "g1"}
        return original(data, status, **headers)

    monkeypatch.setattr(plcnext_sim, "_json", other_id)
    with pytest.raises(PlcProtocolError, match="answered group 'g1'"):
        await plcnext_client.read([TEMPERATURE])


async def test_writes_refused_in_part(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient
) -> None:
    """An unknown variable in a write fails alone (halves); the others are written."""
    results = await plcnext_client.write({PUMP: True, GONE: 1, SPEED: 5})
    assert isinstance(results[GONE].error, PlcAddressError)
    assert results[PUMP].ok
    assert results[SPEED].ok
    assert plcnext_sim.get("MainInstance.Pump") is True
    assert plcnext_sim.get("MainInstance.Speed") == 5
    results = await plcnext_client.write({GONE: 2})
    assert isinstance(results[GONE].error, PlcAddressError)


@pytest.mark.parametrize("answer", [{"apiVersion": "1.8.0.0"}, None], ids=["no list", "empty"])
async def test_write_answered_without_results(
    plcnext_sim: PlcnextSimulator,
    plcnext_client: PlcnextClient,
    monkeypatch: pytest.MonkeyPatch,
    answer: dict[str, Any] | None,
) -> None:
    """A 200 without per-variable results counts as written (the status says it was)."""
    from aiohttp import web

    def bare(*_args: Any) -> web.Response:
        if answer is None:
            return web.Response(status=200)
        return web.json_response(answer)

    monkeypatch.setattr(plcnext_sim, "_write", bare)
    results = await plcnext_client.write({PUMP: True})
    assert results[PUMP].ok


async def test_write_failures_by_status(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A write the PLC cannot serve (5xx) fails the whole call; 403 of one is refused alone."""

    def broken(*_args: Any) -> Any:
        raise Fault(500, "internal")

    monkeypatch.setattr(plcnext_sim, "_write", broken)
    with pytest.raises(PlcConnectionError):
        await plcnext_client.write({PUMP: True, SPEED: 1})

    def forbidden(*_args: Any) -> Any:
        raise Fault(403, "denied")

    monkeypatch.setattr(plcnext_sim, "_write", forbidden)
    results = await plcnext_client.write({PUMP: True, SPEED: 1})
    assert all(isinstance(r.error, PlcWriteRefusedError) for r in results.values())
