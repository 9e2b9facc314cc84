"""TecoApi TIME/TOD and PLCnext TIME/LTIME as durations: decoded, checked, written, refused."""

from __future__ import annotations

from datetime import timedelta
from typing import Any
from zoneinfo import ZoneInfo

import pytest

from custom_components.plc_bridge.plc import PlcValueError, Point, ValueKind
from custom_components.plc_bridge.plc.durations import clock_duration, clock_text
from custom_components.plc_bridge.plc.vendors.plcnext import PlcnextClient
from custom_components.plc_bridge.plc.vendors.plcnext.codec import decode, encode
from custom_components.plc_bridge.plc.vendors.tecomat import TecomatClient
from simulators.plcnext import PlcnextSimulator
from simulators.tecomat import TecomatSimulator

PRAGUE = ZoneInfo("Europe/Prague")
RUNTIME = Point("MainInstance.Runtime", "TIME")
UPTIME = Point("MainInstance.Uptime", "LTIME")
SPEED = Point("MainInstance.Speed", "INT")
TECO_TIME = Point("plcData.varTime", "TIME")
TECO_TOD = Point("plcData.varTod", "TOD")
TECO_INT = Point("plcData.varInt", "INT")
LTIME_MAX = timedelta(microseconds=(2**63 - 1) // 1000)


def test_kinds() -> None:
    """Both vendors' time types are durations."""
    for client, kinds in ((PlcnextClient, ("TIME", "LTIME")), (TecomatClient, ("TIME", "TOD"))):
        for kind in kinds:
            assert client.value_kind(Point("a.b", kind)) is ValueKind.DURATION


@pytest.mark.parametrize(
    ("kind", "raw", "value"),
    [
        ("TIME", 90_000, timedelta(seconds=90)),
        ("TIME", "-250", timedelta(milliseconds=-250)),  # a count sent as text (READINGS 13)
        ("TIME", -(2**31), timedelta(milliseconds=-(2**31))),
        ("LTIME", 5_000_000_000, timedelta(seconds=5)),
        ("LTIME", 1_499, timedelta(microseconds=1)),  # nanoseconds rounded to microseconds
        ("LTIME", 2**63 - 1, timedelta(microseconds=2**63 // 1000 + 1)),
    ],
)
def test_plcnext_decode(kind: str, raw: Any, value: timedelta) -> None:
    assert decode(kind, raw, PRAGUE, "v") == value


@pytest.mark.parametrize(
    ("kind", "value", "sent"),
    [
        ("TIME", 1.5, 1_500),
        ("TIME", "-0.25", -250),
        ("TIME", "00:01:30.5", 90_500),
        ("TIME", 0.0004, 0),  # a TIME counts whole milliseconds
        ("TIME", timedelta(milliseconds=2**31 - 1), 2**31 - 1),
        ("LTIME", 1e-6, 1_000),
        ("LTIME", timedelta(days=-106_751, seconds=-85_636, microseconds=-854_775), -(2**63) + 808),
        ("LTIME", LTIME_MAX, 2**63 - 808),
    ],
)
def test_plcnext_written(kind: str, value: Any, sent: int) -> None:
    """A duration goes as the count the PLC keeps: TIME milliseconds, LTIME nanoseconds."""
    checked = PlcnextClient.validate_value(Point("a.b", kind), value)
    assert isinstance(checked, timedelta)
    assert encode(kind, checked, PRAGUE) == sent


@pytest.mark.parametrize(
    ("kind", "value", "message"),
    [
        ("TIME", 2**31 / 1000, "a TIME holds -2147483.648..2147483.647 s, not 2147483.648 s"),
        ("TIME", -2147483.649, "not -2147483.649 s"),
        ("TIME", "forever", "takes a TIME in seconds or as hh:mm:ss.zzz"),
        ("TIME", True, "takes a TIME"),
        ("LTIME", 9_223_372_036.855, "a LTIME holds -9223372036.854775..9223372036.854775 s"),
        ("LTIME", 10**400, "outside the range of a LTIME"),
    ],
)
def test_plcnext_refused(kind: str, value: Any, message: str) -> None:
    with pytest.raises(PlcValueError, match=message):
        PlcnextClient.validate_value(Point("a.b", kind), value)


def test_clock_text() -> None:
    """The clock form keeps hours past a day, and microseconds only where there are some."""
    assert clock_text(timedelta(milliseconds=2**31 - 1)) == "596:31:23.647"
    assert clock_text(timedelta(microseconds=-1_500)) == "-00:00:00.001500"
    assert clock_duration(" 1:02:03.4 ") == timedelta(hours=1, minutes=2, seconds=3.4)
    assert clock_duration("1:60:00") is None


async def test_plcnext_poll_and_write(
    plcnext_sim: PlcnextSimulator, plcnext_client: PlcnextClient
) -> None:
    """Durations read and written through the REST interface; a bad one fails alone."""
    points = [RUNTIME, UPTIME, SPEED]
    read = (await plcnext_client.read(points)).values
    assert read[RUNTIME].value == timedelta(seconds=90)
    assert read[UPTIME].value == timedelta(seconds=5)
    await plcnext_client.write({RUNTIME: 1.5})
    assert plcnext_sim.get(RUNTIME.address) == 1_500
    before = plcnext_sim.requests
    with pytest.raises(PlcValueError):
        await plcnext_client.write({RUNTIME: 2_147_484})
    assert plcnext_sim.requests == before  # refused before anything is sent
    plcnext_sim.set(RUNTIME.address, "soon")
    read = (await plcnext_client.read(points)).values
    assert not read[RUNTIME].ok
    assert read[UPTIME].value == timedelta(seconds=5)
    assert read[SPEED].value == -1200


async def test_tecomat_poll_and_write(
    tecomat_sim: TecomatSimulator, tecomat_client: TecomatClient
) -> None:
    """TIME and TOD read and written as hh:mm:ss.zzz; a bad answer fails that point alone."""
    points = [TECO_TIME, TECO_TOD, TECO_INT]
    read = (await tecomat_client.read(points)).values
    assert read[TECO_TIME].value == timedelta(hours=120, minutes=2, seconds=3.45)
    assert read[TECO_TOD].value == timedelta(hours=7, minutes=30)
    assert (await tecomat_client.write({TECO_TIME: 90.5}))[TECO_TIME].ok
    assert tecomat_sim.get(TECO_TIME.address) == 90_500
    before = tecomat_sim.requests
    with pytest.raises(PlcValueError, match=r"a TOD holds .*, not 86400 s"):
        await tecomat_client.write({TECO_TOD: timedelta(days=1)})
    with pytest.raises(PlcValueError, match=r"a TIME holds .*, not -1 s"):
        await tecomat_client.write({TECO_TIME: -1})
    assert tecomat_sim.requests == before
    tecomat_sim.rewrite = lambda body: body.replace(b'"07:30:00.000"', b'"7h"')
    read = (await tecomat_client.read(points)).values
    assert not read[TECO_TOD].ok
    assert read[TECO_TIME].value == timedelta(seconds=90.5)
    assert read[TECO_INT].ok
