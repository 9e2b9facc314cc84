"""The PLCnext client against the REST simulator, in both error modes: polls, renewals, writes."""

from __future__ import annotations

from datetime import datetime
from typing import TYPE_CHECKING
from zoneinfo import ZoneInfo

import pytest

from custom_components.plc_bridge.plc import (
    PlcAddressError,
    PlcAuthenticationError,
    PlcValueError,
    PlcWriteRefusedError,
    Point,
)
from custom_components.plc_bridge.plc.vendors.plcnext import PlcnextClient
from simulators.plcnext import VIEWER_USER, PlcnextSimulator

if TYPE_CHECKING:
    from .plcnext_fixtures import ConfigFactory


PRAGUE = ZoneInfo("Europe/Prague")
TEMPERATURE = Point("MainInstance.Temperature", "REAL")
PUMP = Point("MainInstance.Pump", "BOOL")
COUNTER = Point("MainInstance.Counter", "DINT")
LEVEL = Point("MainInstance.Levels[2]", "INT")
WEIGHT = Point("MainInstance.Recipe.Weight", "REAL")
UNKNOWN = Point("MainInstance.Gone", "INT")
POINTS = [TEMPERATURE, PUMP, COUNTER, LEVEL, WEIGHT]


def values(result: object) -> dict[str, object]:
    """Return the values of a read by address (errors by type name)."""
    shown: dict[str, object] = {}
    for point, outcome in result.values.items():  # type: ignore[attr-defined]
        shown[point.address] = outcome.value if outcome.ok else type(outcome.error).__name__
    return shown


EXPECTED = {
    TEMPERATURE.address: 21.5,
    PUMP.address: False,
    COUNTER.address: 799244562,
    LEVEL.address: 20,
    WEIGHT.address: 2.5,
}


async def test_one_request_per_poll(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient
) -> None:
    """The first poll registers the group; every later poll is one group read."""
    assert values(await plcnext_client.read(POINTS)) == EXPECTED
    for _ in range(3):
        result = await plcnext_client.read(POINTS)
        assert plcnext_client.metrics.last_poll_requests == 1
    assert values(result) == EXPECTED
    assert result.status.extra["project_crc"] == str(plcnext_sim.crc)
    assert PlcnextClient.requests_for(POINTS) == 1


@pytest.mark.parametrize("text", [False, True], ids=["numbers", "text"])
async def test_values_as_text(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient, text: bool
) -> None:
    """Values sent as strings of digits or words decode as numbers and booleans."""
    plcnext_sim.text_values = text
    assert values(await plcnext_client.read(POINTS)) == EXPECTED


async def test_token_expiry_mid_polling(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient
) -> None:
    """A refused token is renewed once (two login requests), and the poll goes on."""
    await plcnext_client.read(POINTS)
    plcnext_sim.access.expire_tokens()
    plcnext_sim.set("MainInstance.Temperature", 19.5)
    result = await plcnext_client.read(POINTS)
    assert values(result)[TEMPERATURE.address] == 19.5
    assert plcnext_client.metrics.last_poll_requests == 4  # refused, 2 login steps, again
    assert plcnext_client.metrics.session_renewals == 1
    await plcnext_client.read(POINTS)
    assert plcnext_client.metrics.last_poll_requests == 1


async def test_session_loss_mid_polling(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient
) -> None:
    """A session the PLC no longer knows (410) is created again, and the read repeated."""
    await plcnext_client.read(POINTS)
    plcnext_sim.access.expire_sessions()
    assert values(await plcnext_client.read(POINTS)) == EXPECTED
    assert plcnext_client.metrics.last_poll_requests == 3
    assert len(plcnext_sim.access.sessions) == 1


async def test_sessions_last_four_poll_intervals(
    plcnext_sim: PlcnextSimulator, plcnext_config: ConfigFactory
) -> None:
    """Polled every 600 s: the session and the one made after a loss last 2,400 s each.

    Before: a session made again after a loss lasted 300 s, gone at every later poll.
    """
    client = PlcnextClient(plcnext_config(poll_interval=600.0))
    try:
        await client.connect()
        assert [s.timeout for s in plcnext_sim.access.sessions.values()] == [2400.0]
        plcnext_sim.access.expire_sessions()
        await client.read(POINTS)
        assert [s.timeout for s in plcnext_sim.access.sessions.values()] == [2400.0]
    finally:
        await client.close()


async def test_group_expiry_mid_polling(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient
) -> None:
    """A group the PLC dropped (404) is registered again: no value lost."""
    await plcnext_client.read(POINTS)
    plcnext_sim.expire_groups()
    assert values(await plcnext_client.read(POINTS)) == EXPECTED
    assert plcnext_client.metrics.last_poll_requests == 3


async def test_long_poll_interval_reads_variables(
    plcnext_sim: PlcnextSimulator, plcnext_config: ConfigFactory
) -> None:
    """Polled every 300 s, a group would be gone at each poll (3 requests): variables, 1.

    Before: every poll of a PLC polled less often than its group lasts cost three requests.
    """
    client = PlcnextClient(plcnext_config(poll_interval=300.0))
    try:
        await client.connect()
        for _ in range(3):
            plcnext_sim.expire_groups()  # 300 s later: any group would be gone
            result = await client.read(POINTS)
            assert client.metrics.last_poll_requests == 1
            assert values(result) == EXPECTED
        assert not plcnext_sim.groups.report()
    finally:
        await client.close()


@pytest.mark.parametrize("keep_groups", [False, True])
async def test_program_download_mid_polling(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient, keep_groups: bool
) -> None:
    """A new projectCRC re-registers; a renamed variable fails alone, none shifts to another."""
    plcnext_sim.keep_groups = keep_groups
    await plcnext_client.read(POINTS)
    plcnext_sim.download({"Arp.Plc.Eclr/MainInstance.Pump": "Arp.Plc.Eclr/MainInstance.PumpOn"})
    result = await plcnext_client.read(POINTS)
    assert values(result) == EXPECTED | {PUMP.address: "PlcAddressError"}
    assert result.status.extra["project_crc"] == str(plcnext_sim.crc)
    await plcnext_client.read(POINTS)
    assert plcnext_client.metrics.last_poll_requests == 1
    plcnext_sim.download({"Arp.Plc.Eclr/MainInstance.PumpOn": "Arp.Plc.Eclr/MainInstance.Pump"})
    assert values(await plcnext_client.read(POINTS)) == EXPECTED


async def test_unknown_names_fail_alone(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient
) -> None:
    """Unknown names are left out of the group; later polls cost one request."""
    result = await plcnext_client.read([*POINTS, UNKNOWN, Point("x[", "INT")])
    shown = values(result)
    assert shown.pop(UNKNOWN.address) == "PlcAddressError"
    assert shown.pop("x[") == "PlcAddressError"
    assert shown == EXPECTED
    await plcnext_client.read([*POINTS, UNKNOWN])
    assert plcnext_client.metrics.last_poll_requests == 1


@pytest.mark.parametrize("entries", [False, True])
async def test_on_demand_read(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient, entries: bool
) -> None:
    """A read outside polls reads variables (one GET) and leaves the poll's group alone."""
    plcnext_sim.unknown_entries = entries
    result = await plcnext_client.read([*POINTS, UNKNOWN], poll=False)
    assert values(result) == EXPECTED | {UNKNOWN.address: "PlcAddressError"}
    assert not plcnext_sim.groups


@pytest.mark.parametrize("bodies", ["json", "form"])
async def test_group_body_forms(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient, bodies: str
) -> None:
    """A PLC taking only one body form for a group registration gets that form."""
    plcnext_sim.bodies = bodies
    for _ in range(2):
        assert values(await plcnext_client.read(POINTS)) == EXPECTED
    assert plcnext_client.metrics.last_poll_requests == 1


async def test_writes(plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient) -> None:
    """One PUT for every value; a read-only variable is refused alone."""
    stamp = datetime(2026, 11, 26, 12, 30, tzinfo=PRAGUE)
    before = plcnext_sim.requests
    results = await plcnext_client.write(
        {
            PUMP: True,
            Point("MainInstance.Setpoint", "REAL"): 23.5,
            Point("MainInstance.Big", "ULINT"): 2**64 - 1,
            Point("MainInstance.Label", "WSTRING"): "Straße ✓",
            Point("MainInstance.Clock", "DT"): stamp,
        }
    )
    assert all(result.ok for result in results.values())
    assert plcnext_sim.requests - before == 1
    assert plcnext_sim.get("MainInstance.Pump") is True
    assert plcnext_sim.get("MainInstance.Big") == 2**64 - 1
    assert plcnext_sim.get("MainInstance.Clock") == "2026-11-26T11:30:00.000Z"
    assert await plcnext_client.read_clock() == stamp
    results = await plcnext_client.write({TEMPERATURE: 1.0, PUMP: False})
    assert isinstance(results[TEMPERATURE].error, PlcWriteRefusedError)
    assert results[PUMP].ok
    assert plcnext_sim.get("MainInstance.Pump") is False


@pytest.mark.parametrize(
    ("point", "value"),
    [
        (Point("MainInstance.Speed", "INT"), 40000),
        (Point("MainInstance.Setpoint", "REAL"), 1e39),
        (PUMP, "maybe"),
        (Point("MainInstance.Message", "STRING"), "✓"),
        (Point("MainInstance.Clock", "DT"), "yesterday"),
        (Point("MainInstance.Tiny", "USINT"), -1),
    ],
)
async def test_values_checked_before_sending(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient, point: Point, value: object
) -> None:
    """A value that does not fit its type is refused before any request."""
    before = plcnext_sim.requests
    with pytest.raises(PlcValueError):
        await plcnext_client.write({point: value})  # type: ignore[dict-item]
    assert plcnext_sim.requests == before


async def test_read_only_user(plcnext_config: ConfigFactory) -> None:
    """A user without EHmiChanger reads, and its writes are refused clearly."""
    client = PlcnextClient(plcnext_config(username=VIEWER_USER))
    await client.connect()
    try:
        assert values(await client.read(POINTS)) == EXPECTED
        result = (await client.write({PUMP: True}))[PUMP]
        assert isinstance(result.error, PlcWriteRefusedError)
    finally:
        await client.close()


async def test_wrong_password(plcnext_config: ConfigFactory) -> None:
    """A refused user is an authentication error (reauth), in either error mode."""
    client = PlcnextClient(plcnext_config(password="wrong"))
    try:
        with pytest.raises(PlcAuthenticationError):
            await client.connect()
    finally:
        await client.close()


async def test_without_user_authentication(plcnext_config: ConfigFactory) -> None:
    """A PLC with user authentication off is used without a login."""
    sim = PlcnextSimulator(auth=False)
    await sim.start()
    client = PlcnextClient(
        plcnext_config(port=sim.port, fingerprint=sim.fingerprint, username="", password="")
    )
    try:
        await client.connect()
        assert values(await client.read(POINTS)) == EXPECTED
        assert sim.access.logins == 0
    finally:
        await client.close()
        await sim.stop()


async def test_missing_user(plcnext_config: ConfigFactory) -> None:
    """A PLC that asks for a user, with none configured: connecting fails (reauth, form)."""
    client = PlcnextClient(plcnext_config(username="", password=""))
    try:
        with pytest.raises(PlcAuthenticationError, match="user authentication on"):
            await client.connect()
        with pytest.raises(PlcAuthenticationError, match="asks for a user"):
            await client.read(POINTS)
    finally:
        await client.close()


async def test_browse(plcnext_client: PlcnextClient) -> None:
    """The dictionary's variables with type and read-only flag; arrays and structs as leaves."""
    items = {item.address: item for item in await plcnext_client.browse()}
    assert items["Arp.Plc.Eclr/MainInstance.Temperature"].read_only
    assert items["Arp.Plc.Eclr/MainInstance.Temperature"].data_type == "REAL"
    assert items["Arp.Plc.Eclr/MainInstance.Pump"].platform == "switch"
    assert items["Arp.Plc.Eclr/MainInstance.Levels[1]"].data_type == "INT"
    assert "Arp.Plc.Eclr/MainInstance.Levels[0]" not in items
    assert "Arp.Plc.Eclr/MainInstance.Recipe.Ready" in items
    for address, item in items.items():
        assert PlcnextClient.validate_point(Point(address, item.data_type)).address == address


async def test_device_info(plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient) -> None:
    """The service description: API version pinned, projectCRC, user authentication."""
    device = await plcnext_client.connect()
    assert device.vendor == "plcnext"
    assert device.extra["api_path"] == "/_pxc_api/v1.8"
    assert device.extra["project_crc"] == str(plcnext_sim.crc)
    assert device.extra["user_authentication"] == "on"


def test_paths() -> None:
    """Paths without a component live in Arp.Plc.Eclr/; bad ones are address errors."""
    assert PlcnextClient.validate_point(Point(" Main.Arr[ 3 ].x ", "int")) == Point(
        "Arp.Plc.Eclr/Main.Arr[3].x", "INT"
    )
    for bad in ("", "Main..x", "Main[2; 4]", "1abc", "Main.x[", "a/b/"):
        with pytest.raises(PlcAddressError):
            PlcnextClient.validate_point(Point(bad, "INT"))
    with pytest.raises(PlcAddressError):
        PlcnextClient.validate_point(Point("Main.x", "STRUCT"))


async def test_every_name_unknown_watches_the_program(
    plcnext_sim: PlcnextSimulator, plcnext_config: ConfigFactory
) -> None:
    """With no name known there is no group: a groups report (one request) sees a download."""
    client = PlcnextClient(plcnext_config(options={}))  # no clock variable in the group either
    points = [UNKNOWN, Point("MainInstance.Later", "REAL")]
    try:
        await client.connect()
        result = await client.read(points)
        assert set(values(result).values()) == {"PlcAddressError"}
        for _ in range(2):
            await client.read(points)
            assert client.metrics.last_poll_requests == 1
        assert plcnext_sim.calls["GET groups"] == 3  # the report, not a group read
        assert not plcnext_sim.groups
        renamed = {"Arp.Plc.Eclr/MainInstance.Speed": "Arp.Plc.Eclr/MainInstance.Later"}
        plcnext_sim.download(renamed)
        result = await client.read(points)
        assert values(result) == {UNKNOWN.address: "PlcAddressError", "MainInstance.Later": -1200.0}
        await client.read(points)
        assert client.metrics.last_poll_requests == 1
    finally:
        await client.close()


async def test_clock_rides_in_the_group(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient
) -> None:
    """The clock variable is read with the poll's group (status.clock), at no extra request."""
    result = await plcnext_client.read(POINTS)
    assert result.status.clock == datetime(2026, 11, 26, 9, 0, tzinfo=PRAGUE)
    result = await plcnext_client.read(POINTS)
    assert plcnext_client.metrics.last_poll_requests == 1
    assert plcnext_client.can_set_clock
    when = datetime(2026, 11, 26, 14, 0, tzinfo=PRAGUE)
    await plcnext_client.set_clock(when)
    assert (await plcnext_client.read(POINTS)).status.clock == when
    assert await plcnext_client.read_clock() == when
