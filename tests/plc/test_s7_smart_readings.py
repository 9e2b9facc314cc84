"""S7-200 SMART readings of issue 23 (READINGS.md rows 17-19), under every firmware's readings.

A string holding bytes beyond ASCII put in the reply in each way a web server might, a REAL
printed in each way a firmware might, and busy answers in a row.
"""

from __future__ import annotations

import itertools
import logging
from typing import Any

import pytest

from custom_components.plc_bridge.plc import PlcConnectionError, Point
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient, rpc
from simulators.s7_smart import HttpFault, S7SmartSimulator
from simulators.s7_smart.memory import REAL_FORMATS
from simulators.s7_smart.server import STRINGS
from tests.loopback import connected

from .conftest import ConfigFactory
from .s7_smart_fixtures import FIRMWARES, configure, fast_backoff, firmware_id

pytestmark = pytest.mark.no_pacing

WORD = Point("VW0", "signed")
STRING = Point("VB500", "string")
REAL = Point("VD4", "float")
DEGREES = b"25\xb0C"  # `25°C` as a Western Micro/WIN SMART program stores it
CHINESE = "温度".encode("gbk")  # "temperature" as a Chinese edition stores it
SHOWN = {reading: DEGREES.decode("latin-1") for reading in STRINGS} | {
    "gbk": DEGREES.decode("gbk"),  # the firmware's own reading of the bytes, sent in UTF-8
    "gbk-declared": DEGREES.decode("gbk"),
}


@pytest.fixture(autouse=True, params=FIRMWARES, ids=firmware_id)
def firmware(request: pytest.FixtureRequest, s7_smart_sim: S7SmartSimulator) -> dict[str, Any]:
    """Run every test under each firmware's readings of rows 1-10."""
    configure(s7_smart_sim, request.param)
    return dict(request.param)


@pytest.fixture(autouse=True)
def quick_resends(monkeypatch: pytest.MonkeyPatch) -> None:
    """Busy reads are sent again after 10 ms (1 s in use), doubling."""
    fast_backoff(monkeypatch)


@pytest.mark.parametrize("strings", STRINGS)
async def test_string_beyond_ascii_costs_no_other_point(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient, strings: str
) -> None:
    """`25°C` put in V memory by the program (issue 23: "not JSON" at every poll): every point
    has its value, the string its bytes, however the web server puts them in the reply."""
    s7_smart_sim.strings = strings
    s7_smart_sim.put_string("VB500", DEGREES)
    s7_smart_sim.set("VW0", 7)
    s7_smart_sim.set("VD4", 22.3, "float")
    for _poll in range(2):
        values = (await s7_smart_client.read([WORD, STRING, REAL])).values
        assert values[WORD].value == 7
        assert values[REAL].value == 22.3
        assert values[STRING].value == SHOWN[strings]


@pytest.mark.parametrize(
    ("strings", "shown", "told"),
    [
        ("raw", CHINESE.decode("latin-1"), True),  # the client cannot tell: bytes kept, told
        ("latin-1", CHINESE.decode("latin-1"), False),  # declared: right by its declaration
        ("utf-8", CHINESE.decode("latin-1"), False),  # the firmware read them so
        ("escaped", CHINESE.decode("latin-1"), False),
        ("gbk", "温度", False),
        ("gbk-declared", "温度", False),
    ],
)
async def test_text_of_another_code_page(  # noqa: PLR0917 - fixtures and parameters
    s7_smart_sim: S7SmartSimulator,
    s7_smart_client: S7SmartClient,
    caplog: pytest.LogCaptureFixture,
    strings: str,
    shown: str,
    told: bool,
) -> None:
    """GBK bytes: shown as the firmware or its declared charset reads them; sent undeclared
    they are shown one character a byte (every byte kept) and the log says so, once."""
    s7_smart_sim.strings = strings
    s7_smart_sim.put_string("VB500", CHINESE)
    caplog.set_level(logging.WARNING)
    for _poll in range(3):
        value = (await s7_smart_client.read([STRING])).values[STRING].value
        assert value == shown
    assert isinstance(value, str)
    if strings in ("raw", "latin-1"):
        assert value.encode("latin-1") == CHINESE
    said = [r for r in caplog.records if "not UTF-8" in r.getMessage()]
    assert len(said) == (1 if told else 0)


@pytest.mark.parametrize("real_format", REAL_FORMATS)
async def test_real_shown_as_its_float32(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient, real_format: str
) -> None:
    """22.3, not 22.299999237060547 nor 22.299999, in reads and in a write's result."""
    s7_smart_sim.real_format = real_format
    values = [22.3, -0.1, 0.001, 123456.7, 3.4e38, 1.5]
    points = [Point(f"VD{4 * index}", "float") for index in range(len(values))]
    for point, value in zip(points, values, strict=True):
        s7_smart_sim.set(point.address, value, "float")
    read = (await s7_smart_client.read(points)).values
    assert [read[point].value for point in points] == values
    written = await s7_smart_client.write({REAL: 22.299999237060547})
    assert written[REAL].value == 22.3
    assert (await s7_smart_client.read([REAL])).values[REAL].value == 22.3


@pytest.mark.parametrize("busy", [HttpFault(503), HttpFault(404), HttpFault(500, "<html/>")])
@pytest.mark.parametrize("times", [1, 2, 3])
async def test_busy_answers_in_a_row(
    s7_smart_sim: S7SmartSimulator, s7_smart_client: S7SmartClient, busy: HttpFault, times: int
) -> None:
    """Two or three busy answers in a row (issue 23: 4 polls of 12 failed) cost resends only."""
    s7_smart_sim.set("VW0", 5)
    s7_smart_sim.busy, s7_smart_sim.busy_status = times, busy
    before = s7_smart_sim.requests
    assert (await s7_smart_client.read([WORD])).values[WORD].value == 5
    assert s7_smart_sim.requests - before == times + 1


@pytest.mark.parametrize("retry_after", ["0", None])
async def test_busy_for_longer_than_an_interval_fails_the_poll(
    s7_smart_sim: S7SmartSimulator,
    s7_smart_config: ConfigFactory,
    monkeypatch: pytest.MonkeyPatch,
    retry_after: str | None,
) -> None:
    """Resent as long as the resend leaves within the poll interval (30, 60, 120 ms; 240 ms
    more would end past 440 ms), then the poll fails and the next one is as ever; a write is
    never sent twice."""
    monkeypatch.setattr(rpc, "BUSY_BACKOFF", 0.03)
    headers = {"Retry-After": retry_after} if retry_after else {}
    s7_smart_sim.busy_status = HttpFault(429 if retry_after else 503, headers=headers)
    async with connected(S7SmartClient(s7_smart_config(poll_interval=0.44))) as client:
        s7_smart_sim.busy = 3
        assert (await client.read([WORD])).values[WORD].ok
        s7_smart_sim.busy, before = 4, s7_smart_sim.requests
        with pytest.raises(PlcConnectionError, match="4 times in a row"):
            await client.read([WORD])
        assert s7_smart_sim.requests - before == 4
        assert (await client.read([WORD])).values[WORD].ok
        s7_smart_sim.busy, before = 1, s7_smart_sim.requests
        with pytest.raises(PlcConnectionError, match="HTTP"):
            await client.write({WORD: 1})
        assert s7_smart_sim.requests - before == 1
        assert s7_smart_sim.calls["write"] == 0


async def test_busy_back_off_keeps_the_pacing(
    s7_smart_sim: S7SmartSimulator,
    s7_smart_config: ConfigFactory,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The resends wait 100, 200, 400 ms, and never less than the pacing between requests."""
    monkeypatch.setattr(S7SmartClient, "request_interval", 0.15)
    monkeypatch.setattr(rpc, "BUSY_BACKOFF", 0.1)
    async with connected(S7SmartClient(s7_smart_config(poll_interval=1.0))) as client:
        s7_smart_sim.busy = 3
        first = len(s7_smart_sim.arrivals)
        assert (await client.read([WORD])).values[WORD].ok
    times = s7_smart_sim.arrivals[first : first + 4]
    gaps = [later - earlier for earlier, later in itertools.pairwise(times)]
    assert all(gap >= least - 0.005 for gap, least in zip(gaps, [0.15, 0.2, 0.4], strict=True))


def test_busy_delays() -> None:
    """Doubling from the pacing, as many as fit the poll interval."""
    assert rpc.busy_delays(10.0, 1.0) == [1.0, 2.0, 4.0]
    assert rpc.busy_delays(5.0, 1.0) == [1.0, 2.0]
    assert rpc.busy_delays(0.5, 1.0) == []
