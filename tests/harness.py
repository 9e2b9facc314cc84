"""The Home Assistant tests' one vendor harness: each PLC family's simulator, entry and points.

`PlcUnderTest` is one family's PLC as the tests meet it: its simulator started on loopback
(time frozen until every entry is unloaded), the entry data its flow stores, its points, a
machine of any points added, a value read or set at the simulator, the requests it served.
The fixture `plc` is the family a test asks for (`@pytest.mark.parametrize("plc", [...],
indirect=True)`; the S7-200 SMART when it asks none), `every_plc` each of the six families.
The `<family>_ha_sim` fixtures are the same simulators alone, for the tests of one family;
the protocol tests' `<family>_sim` (tests/plc/) are bare simulators without Home Assistant.
Registered for every test through `pytest_plugins` in tests/conftest.py.
"""

from __future__ import annotations

from collections.abc import AsyncGenerator, AsyncIterator, Awaitable, Callable, Iterable
from contextlib import AsyncExitStack, asynccontextmanager
from dataclasses import dataclass, field
from datetime import timedelta
import re
import struct
import threading
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import ConfigSubentry
from homeassistant.const import CONF_ATTRIBUTE, CONF_ENTITY_ID
from homeassistant.core import HomeAssistant
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, async_fire_time_changed

from custom_components.plc_bridge.const import (
    CONF_ADDRESS,
    CONF_COOLDOWN,
    CONF_DATA_TYPE,
    CONF_DEFAULT,
    CONF_OFFSET,
    CONF_OPTIONS,
    CONF_RESEND,
    CONF_SCALE,
    CONF_SEND_ON_START,
    CONF_VALUE_MAP,
    DOMAIN,
    SUBENTRY_EXPOSE,
)
from custom_components.plc_bridge.plc import PlcConnectionError, PlcTimeoutError
from custom_components.plc_bridge.plc.http import URGENT
from custom_components.plc_bridge.plc.vendors.logo.options import DEFAULT_TSAPS
from custom_components.plc_bridge.plc.vendors.s7 import S7Client
from custom_components.plc_bridge.runtime.expose import BATCH_WINDOW
from simulators import plcnext, tecomat
from simulators.logo import LogoSimulator
from simulators.plcnext import PlcnextSimulator
from simulators.s7 import S7Simulator
from simulators.s7_smart import S7SmartSimulator
from simulators.softplc import SoftplcSimulator
from simulators.tecomat import TecomatSimulator
from tests.entries import (
    CLOCK,
    POINTS,
    PointData,
    add_entry,
    entry_data,
    make_entry,
    point,
    serving,
    set_up,
    sim_data,
    unload_all,
)
from tests.loopback import running


def fill_s7_smart(sim: S7SmartSimulator) -> None:
    """Put the clock and the values of POINTS into an S7-200 SMART simulator."""
    sim.clock = CLOCK
    sim.set("VD100", 21.5, "float")
    sim.set("VW10", 235)
    sim.set("VB200", "Line 1", "string")
    sim.set("VD300", [1, 2, 171, 205], "raw")
    sim.set("I0.0", True)
    sim.set("VW20", 40)


@pytest.fixture
async def s7_smart_ha_sim(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory
) -> AsyncGenerator[S7SmartSimulator]:
    """A started S7-200 SMART simulator (HTTPS, own CA) holding the values of POINTS.

    Time is frozen from before any entry is set up until every entry is unloaded: the clients
    pace their requests by the monotonic clock, which the freezer moves by years.
    """
    async with started(hass, "s7_smart") as plc:
        yield plc.sim


@pytest.fixture
async def flow_sim() -> AsyncGenerator[S7SmartSimulator]:
    """An S7-200 SMART simulator on 127.0.0.1 for the flow tests (no values set, time runs)."""
    async with running(S7SmartSimulator()) as sim:
        yield sim


@pytest.fixture
def flow_entry(hass: HomeAssistant, flow_sim: S7SmartSimulator) -> MockConfigEntry:
    """A configured (not loaded) entry of the flow tests' simulator, without machines."""
    entry = MockConfigEntry(
        domain=DOMAIN,
        title="Boiler house PLC",
        data=sim_data(flow_sim),
        unique_id=f"{flow_sim.host}:{flow_sim.port}",
        version=2,
    )
    entry.add_to_hass(hass)
    return entry


# S7 (ISO-on-TCP)

S7_ENTRY_ID = "01JPLCBR1DGE00000000S7TEST"
S7_TITLE = "S7-300"
RACK_SLOT = {"connection": "rack_slot", "rack": 0, "slot": 1}

SNAP7_THREADS = ("(_server_loop)", "(_handle_client)")  # python-snap7's server thread targets

type SimFactory = Callable[..., Awaitable[S7Simulator]]

S7_POINTS = [
    point(
        "temperature",
        "Temperature",
        "sensor",
        "DB1.DBD8",
        "REAL",
        unit_of_measurement="°C",
        device_class="temperature",
        state_class="measurement",
    ),
    point("level", "Level", "sensor", "DB1.DBW2", "INT"),
    point("counter", "Counter", "sensor", "MW20", "INT"),
    point("door", "Door", "binary_sensor", "DB1.DBX0.0", "BOOL", device_class="door"),
    point("pump", "Pump", "switch", "M10.1", "BOOL"),
    point("setpoint", "Setpoint", "number", "DB1.DBW4", "INT", min=0.0, max=100.0, step=1.0),
]
"""DB and M points of every platform the tests use (entity ids: `<platform>.s7_300_<name>`)."""


def s7_data(sim: S7Simulator, **options: Any) -> dict[str, Any]:
    """Return the entry data the config flow stores for the simulator (rack 0, slot 1)."""
    return entry_data("s7", sim, ("", ""), options=RACK_SLOT | options)


def make_s7_entry(
    hass: HomeAssistant,
    sim: S7Simulator,
    points: Iterable[PointData] = S7_POINTS,
    **options: Any,
) -> MockConfigEntry:
    """Add an entry of the simulator with the given points (not set up yet)."""
    return add_entry(
        hass,
        title=S7_TITLE,
        entry_id=S7_ENTRY_ID,
        unique_id=S7Simulator.serial,
        data=s7_data(sim, **options),
        points=points,
    )


def spread(count: int) -> list[PointData]:
    """Return `count` REAL sensors over DB1..DB3, 34 bytes apart: the PDU decides the packing."""
    return [
        point(
            f"p{index}",
            f"Point {index}",
            "sensor",
            f"DB{1 + index % 3}.DBD{index // 3 * 34}",
            "REAL",
        )
        for index in range(count)
    ]


def fill(sim: S7Simulator) -> None:
    """Put the values of S7_POINTS into the simulator."""
    sim.set_db(1, 0, b"\x01")  # DB1.DBX0.0 on
    sim.set_db(1, 2, (1234).to_bytes(2, "big"))
    sim.set_db(1, 4, (40).to_bytes(2, "big"))
    sim.set_db(1, 8, bytes.fromhex("41ac0000"))  # 21.5
    sim.set_bytes("M", 20, (-7).to_bytes(2, "big", signed=True))


def no_snap7_thread_left() -> None:
    """Fail when a python-snap7 server thread still runs (a simulator was not stopped)."""
    lingering = [t.name for t in threading.enumerate() if t.name.endswith(SNAP7_THREADS)]
    assert not lingering, f"snap7 server threads left running: {lingering}"


@pytest.fixture
async def s7_ha_sims(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory
) -> AsyncGenerator[SimFactory]:
    """Start S7 simulators built as a test asks; afterwards unload, stop, check no thread stays.

    Time is frozen (the client's reconnect backoff runs on the monotonic clock the freezer moves).
    """
    async with AsyncExitStack() as running_sims:

        async def make(**settings: Any) -> S7Simulator:
            return await running_sims.enter_async_context(running(S7Simulator(**settings)))

        yield make
        await unload_all(hass)
    no_snap7_thread_left()


@pytest.fixture
async def s7_ha_sim(s7_ha_sims: SimFactory) -> S7Simulator:
    """An S7-300-like CPU (rack 0, slot 1, PDU 480, DB1 of 1024 bytes) holding S7_POINTS."""
    sim = await s7_ha_sims()
    fill(sim)
    return sim


@pytest.fixture
def s7_entry(hass: HomeAssistant, s7_ha_sim: S7Simulator) -> MockConfigEntry:
    """The simulator's entry (rack/slot), with S7_POINTS."""
    return make_s7_entry(hass, s7_ha_sim)


@pytest.fixture
async def s7_setup(hass: HomeAssistant, s7_entry: MockConfigEntry) -> MockConfigEntry:
    """The simulator's entry, set up (unloaded by `s7_ha_sims`)."""
    return await set_up(hass, s7_entry)


@pytest.fixture
def s7_fast_reconnect(monkeypatch: pytest.MonkeyPatch) -> None:
    """Keep the reconnect backoff below one poll interval (first 1 s, longest 5 s)."""
    monkeypatch.setattr(S7Client, "reconnect_delay", (1.0, 5.0))


# TecoApi (tecomat)

TECOMAT_ENTRY_ID = "01JPLCBR1DGE00000000TECOMAT"
TECOMAT_SERIAL = "PP 0004"  # GetInfo's plc.serialNumber: the entry's unique id

TECOMAT_POINTS = [
    point(
        "inside",
        "Inside temperature",
        "sensor",
        "Main.myObject2.value",
        "REAL",
        unit_of_measurement="°C",
        device_class="temperature",
        state_class="measurement",
        read_only=True,
    ),
    point(
        "requested",
        "Requested temperature",
        "number",
        "Main.myObject3.value",
        "REAL",
        min=10.0,
        max=30.0,
        step=0.5,
    ),
    point("pump", "Circulation pump", "switch", "Main.pump.value", "BOOL"),
    point("bool1", "Bool 1", "binary_sensor", "plcData.varBool1", "BOOL"),
    point("int", "Int", "sensor", "plcData.varInt", "INT"),
    point("udint", "Salary", "sensor", "myObject.salary", "UDINT"),
    point("time", "Time", "sensor", "plcData.varTime", "TIME"),
    point("element", "Element", "sensor", "arr2[1][3]", "REAL"),
    point("greeting", "Greeting", "text", "plcData.varString", "STRING"),
    point("stamp", "Stamp", "datetime", "plcData.varDT", "DT"),
]
"""Points of several IEC types, chapter 5.3 objects, members and elements, every platform."""


def tecomat_data(sim: TecomatSimulator, **changes: Any) -> dict[str, Any]:
    """Return entry data for the simulator: plain HTTP, default user, Digest, a clock variable."""
    options = {"auth": sim.auth.method, "clock_variable": "setTime"}
    credentials = (tecomat.DEFAULT_USER, tecomat.DEFAULT_PASSWORD)
    return entry_data("tecomat", sim, credentials, options=options) | changes


def make_tecomat_entry(
    hass: HomeAssistant,
    sim: TecomatSimulator,
    points: Iterable[PointData] = TECOMAT_POINTS,
    **changes: Any,
) -> MockConfigEntry:
    """Add an entry of the simulator with the given points (not set up yet)."""
    return add_entry(
        hass,
        title="Fx2 CP2080",
        entry_id=TECOMAT_ENTRY_ID,
        unique_id=TECOMAT_SERIAL,
        data=tecomat_data(sim, **changes),
        points=points,
    )


@pytest.fixture
async def tecomat_ha_sim(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory
) -> AsyncGenerator[TecomatSimulator]:
    """A started Tecomat simulator (Digest, plain HTTP, no benchmark variables).

    Time is frozen until every entry is unloaded, as for the S7-200 SMART fixture.
    """
    async with started(hass, "tecomat") as plc:
        yield plc.sim


@pytest.fixture
async def tecomat_entry(
    hass: HomeAssistant, tecomat_ha_sim: TecomatSimulator
) -> AsyncGenerator[MockConfigEntry]:
    """The simulator's entry with TECOMAT_POINTS, set up (unloaded afterwards)."""
    yield await set_up(hass, make_tecomat_entry(hass, tecomat_ha_sim))
    await unload_all(hass)


@pytest.fixture
async def tecomat_basic_ha_sim(hass: HomeAssistant) -> AsyncGenerator[TecomatSimulator]:
    """A started Tecomat simulator taking Basic authentication over plain HTTP."""
    async with serving(hass, TecomatSimulator(auth="basic", bench=0)) as sim:
        yield sim


# PLCnext

PLCNEXT_ENTRY_ID = "01JPLCBR1DGE00000000PLCNEXT"

PLCNEXT_POINTS = [  # full paths, as the point form stores them
    point(
        "temperature",
        "Temperature",
        "sensor",
        "Arp.Plc.Eclr/MainInstance.Temperature",
        "REAL",
        unit_of_measurement="°C",
        device_class="temperature",
        state_class="measurement",
        read_only=True,
    ),
    point(
        "setpoint",
        "Setpoint",
        "number",
        "Arp.Plc.Eclr/MainInstance.Setpoint",
        "REAL",
        min=10.0,
        max=30.0,
    ),
    point("pump", "Pump", "switch", "Arp.Plc.Eclr/MainInstance.Pump", "BOOL"),
    point("alarm", "Alarm", "binary_sensor", "Arp.Plc.Eclr/MainInstance.Alarm", "BOOL"),
    point("level", "Level 2", "sensor", "Arp.Plc.Eclr/MainInstance.Levels[2]", "INT"),
    point("message", "Message", "text", "Arp.Plc.Eclr/MainInstance.Message", "STRING"),
]


def plcnext_data(sim: PlcnextSimulator, **changes: Any) -> dict[str, Any]:
    """Return entry data for the simulator: pinned certificate, default user, a clock variable."""
    clock = {"clock_variable": "Arp.Plc.Eclr/MainInstance.Clock"}
    credentials = (plcnext.DEFAULT_USER, plcnext.DEFAULT_PASSWORD)
    return entry_data("plcnext", sim, credentials, "pin", clock) | changes


def make_plcnext_entry(
    hass: HomeAssistant,
    sim: PlcnextSimulator,
    points: Iterable[PointData] = PLCNEXT_POINTS,
    **changes: Any,
) -> MockConfigEntry:
    """Add an entry of the simulator with the given points (not set up yet)."""
    return add_entry(
        hass,
        title="PLCnext",
        entry_id=PLCNEXT_ENTRY_ID,
        unique_id=f"{sim.host}:{sim.port}",
        data=plcnext_data(sim, **changes),
        points=points,
    )


@pytest.fixture
async def plcnext_ha_sim(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory
) -> AsyncGenerator[PlcnextSimulator]:
    """A started PLCnext simulator (HTTPS, user authentication on); time frozen meanwhile."""
    async with started(hass, "plcnext") as plc:
        yield plc.sim


@pytest.fixture
async def plcnext_entry(
    hass: HomeAssistant, plcnext_ha_sim: PlcnextSimulator
) -> AsyncGenerator[MockConfigEntry]:
    """The simulator's entry with PLCNEXT_POINTS, set up (unloaded afterwards)."""
    yield await set_up(hass, make_plcnext_entry(hass, plcnext_ha_sim))
    await unload_all(hass)


# SoftPLC (WEB.TLM)

SOFTPLC_ENTRY_ID = "01JPLCBR1DGE00000000SOFTPLC"

SOFTPLC_POINTS = [
    point("temperature", "Temperature", "sensor", "F8:0", "REAL", read_only=True),
    point("count", "Count", "sensor", "N7:5", "INT"),
    point("preset", "Preset", "number", "T4:0.PRE", "INT", min=0.0, max=10000.0, step=1.0),
    point("lamp", "Lamp", "switch", "B3:0/2", "BOOL"),
    point("input", "Input", "binary_sensor", "I:0/0", "BOOL"),
    point("tag", "Important", "sensor", "important_int", "INT"),
]
"""Points of every type: a float, a word, a timer word, bits, a tag."""


def softplc_data(sim: SoftplcSimulator, **changes: Any) -> dict[str, Any]:
    """Return entry data for the simulator (plain HTTP unless it speaks TLS: then pinned)."""
    return entry_data("softplc", sim, None, "pin" if sim.tls else "none") | changes


def make_softplc_entry(
    hass: HomeAssistant,
    sim: SoftplcSimulator,
    points: Iterable[PointData] = SOFTPLC_POINTS,
    **changes: Any,
) -> MockConfigEntry:
    """Add an entry of the simulator with the given points (not set up yet)."""
    return add_entry(
        hass,
        title="SoftPLC",
        entry_id=SOFTPLC_ENTRY_ID,
        unique_id=f"{sim.host}:{sim.port}",
        data=softplc_data(sim, **changes),
        points=points,
    )


@pytest.fixture
async def softplc_ha_sim(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory
) -> AsyncGenerator[SoftplcSimulator]:
    """A started SoftPLC simulator over HTTPS that takes PUTs only with a client certificate."""
    async with started(hass, "softplc") as plc:
        yield plc.sim


@pytest.fixture
async def softplc_http_ha_sim(hass: HomeAssistant) -> AsyncGenerator[SoftplcSimulator]:
    """A started SoftPLC simulator over plain HTTP, without PUT authentication."""
    async with serving(hass, SoftplcSimulator(bench=0)) as sim:
        yield sim


def pem_pair(sim: SoftplcSimulator, *, trusted: bool = True) -> dict[str, str]:
    """Return the vendor options (as a form takes them) of a client certificate and its key."""
    certificate, key = sim.client_certificate(trusted=trusted)
    return {"client_certificate": certificate, "client_key": key}


# LOGO!

LOGO_ENTRY_ID = "01JPLCBR1DGE0000000000LOGO"
LOGO_GENERATION = "0ba8"

LOGO_POINTS = [
    point("i1", "Input 1", "binary_sensor", "I1", "BOOL"),
    point("ai1", "Analog 1", "sensor", "AI1", "INT"),
    point("setpoint", "Setpoint", "number", "VW10", "INT", min=0.0, max=1000.0, step=1.0),
    point("lamp", "Lamp", "switch", "V4.0", "BOOL"),
]
"""A block input, an analog input and VM a LOGO! lets Home Assistant write."""


def logo_data(sim: LogoSimulator) -> dict[str, Any]:
    """Return the entry data the config flow stores for a LOGO! (its default TSAPs)."""
    local, remote = DEFAULT_TSAPS[sim.generation]
    options = {"generation": sim.generation, "local_tsap": local, "remote_tsap": remote}
    return entry_data("logo", sim, ("", ""), options=options)


def make_logo_entry(
    hass: HomeAssistant, sim: LogoSimulator, points: Iterable[PointData] = LOGO_POINTS
) -> MockConfigEntry:
    """Add an entry of the LOGO! with the given points (not set up yet)."""
    return add_entry(
        hass,
        title="LOGO",
        entry_id=LOGO_ENTRY_ID,
        unique_id=f"{sim.host}:{sim.port}",
        data=logo_data(sim),
        points=points,
    )


@pytest.fixture(params=["0ba7", "0ba8", "8_x"])
async def logo_ha_sim(
    request: pytest.FixtureRequest, hass: HomeAssistant
) -> AsyncGenerator[LogoSimulator]:
    """A LOGO! of each generation on loopback, serving its default server TSAP.

    Afterwards every entry is unloaded, the LOGO! stopped, and no snap7 thread may stay.
    """
    async with serving(hass, LogoSimulator(request.param)) as sim:
        yield sim
    no_snap7_thread_left()


def fill_logo(sim: LogoSimulator) -> None:
    """Put the values of LOGO_POINTS into the LOGO!."""
    sim.set_block("I1", True)
    sim.set_block("AI1", 517)
    sim.set_db(1, 10, (321).to_bytes(2, "big"))  # VW10
    sim.set_db(1, 4, b"\x01")  # V4.0


# One harness over the families

type Target = tuple[str, str]
"""An address and its data type."""
PLCNEXT_VARIABLES = "Arp.Plc.Eclr/MainInstance."
SNAP7_TYPES = {"BOOL": "", "INT": ">h", "WORD": ">H", "DINT": ">i", "REAL": ">f"}
_SNAP7_ADDRESS = re.compile(
    r"(?:DB(?P<db>\d+)\.DB(?P<dbsize>[XBWD])|(?P<area>[MV])(?P<size>[BWD]?))"
    r"(?P<byte>\d+)(?:\.(?P<bit>\d))?"
)


def _snap7_place(address: str) -> tuple[str, int, int, int | None]:
    """Return the area ("DB" or "M"), DB number, byte and bit of an S7 or LOGO! VM address."""
    match = _SNAP7_ADDRESS.fullmatch(address)
    if match is None:
        raise ValueError(f"{address!r} is no DB, M or V address the harness reads")
    bit = None if match["bit"] is None else int(match["bit"])
    if match["area"] == "M":
        return "M", 0, int(match["byte"]), bit
    return "DB", int(match["db"] or 1), int(match["byte"]), bit


def _snap7_read(sim: S7Simulator, address: str, data_type: str) -> Any:
    """Return what an S7 simulator (or a LOGO!'s VM) holds at a BOOL, INT, DINT or REAL."""
    area, db, start, bit = _snap7_place(address)
    size = 1 if bit is not None else struct.calcsize(SNAP7_TYPES[data_type])
    raw = sim.get_db(db, start, size) if area == "DB" else sim.get_bytes(area, start, size)
    if bit is not None:
        return bool(raw[0] >> bit & 1)
    return struct.unpack(SNAP7_TYPES[data_type], raw)[0]


def _snap7_write(sim: S7Simulator, address: str, value: Any, data_type: str) -> None:
    """Set what an S7 simulator (or a LOGO!'s VM) holds at a BOOL, INT, DINT or REAL."""
    area, db, start, bit = _snap7_place(address)
    if bit is not None:
        byte = (sim.get_db(db, start, 1) if area == "DB" else sim.get_bytes(area, start, 1))[0]
        raw = bytes([byte | 1 << bit if value else byte & ~(1 << bit)])
    else:
        raw = struct.pack(SNAP7_TYPES[data_type], value)
    if area == "DB":
        sim.set_db(db, start, raw)
    else:
        sim.set_bytes(area, start, raw)


def _softplc_read(sim: SoftplcSimulator, address: str, _data_type: str) -> Any:
    """Return what a SoftPLC simulator holds at `N7:3`, `F8:1` or `B3:0/5`."""
    file, _, rest = address.partition(":")
    element, _, bit = rest.partition("/")
    word = sim.files[file[0], int(file[1:])].words[int(element)]
    return bool(word >> int(bit) & 1) if bit else word


def _softplc_write(sim: SoftplcSimulator, address: str, value: Any, _data_type: str) -> None:
    """Set what a SoftPLC simulator holds at `N7:3` or `B3:0/5` (whole words and bits)."""
    file, _, rest = address.partition(":")
    element, _, bit = rest.partition("/")
    words = sim.files[file[0], int(file[1:])].words
    if bit:
        mask = 1 << int(bit)
        words[int(element)] = words[int(element)] | mask if value else words[int(element)] & ~mask
    else:
        words[int(element)] = value


@dataclass(frozen=True, slots=True)
class Family:
    """What a PLC family's tests need to know of it: its simulator, entry, points and targets."""

    key: str
    simulator: Callable[[], Any]
    fill: Callable[[Any], None]
    entry: Callable[..., MockConfigEntry]
    points: list[PointData]
    prefix: str  # how the family's entity ids start (its entry's title, as a slug)
    bit: str  # the data type of a bit
    word: str  # the data type of a whole number
    real: Target  # where the simulator takes a floating-point value
    flag: Target  # where it takes a bit
    burst: list[Target]  # ten whole numbers (or REALs) the write tests change at once
    read: Callable[[Any, str, str], Any]
    write: Callable[[Any, str, Any, str], None]
    write_call: str | None  # the simulator's count of write requests (None: all requests)
    roles: dict[str, str] = field(default_factory=dict)  # the output tests' cover and button


def _nothing(_sim: Any) -> None:
    """Put nothing into a simulator (it starts with the values its family ships)."""


def _by_path_read(sim: Any, address: str, _data_type: str) -> Any:
    """Return what a simulator holding variables by path holds at one."""
    return sim.get(address)


def _by_path_write(sim: Any, address: str, value: Any, _data_type: str) -> None:
    """Set what a simulator holding variables by path holds at one."""
    sim.set(address, value)


def _softplc_entry(
    hass: HomeAssistant, sim: SoftplcSimulator, points: Iterable[PointData] = SOFTPLC_POINTS
) -> MockConfigEntry:
    """Add the SoftPLC entry with the client certificate its PUTs need."""
    return make_softplc_entry(hass, sim, points, **{CONF_OPTIONS: pem_pair(sim)})


FAMILIES = {
    "s7_smart": Family(
        "s7_smart",
        S7SmartSimulator,
        fill_s7_smart,
        make_entry,
        POINTS,
        "s7_200_smart",
        "signed",
        "signed",
        ("VD400", "float"),
        ("M10.0", "signed"),
        [(f"VW{500 + 2 * i}", "signed") for i in range(10)],
        lambda sim, address, data_type: sim.get(address, data_type),
        lambda sim, address, value, data_type: sim.set(address, value, data_type),
        "write",
        {
            "open": "Q0.4",
            "close": "Q0.5",
            "stop": "Q0.6",
            "open_limit": "I0.1",
            "closed_limit": "I0.2",
            "position": "VW40",
            "status": "VW44",
            "button": "Q0.2",
        },
    ),
    "tecomat": Family(
        "tecomat",
        lambda: TecomatSimulator(bench=0),
        _nothing,
        make_tecomat_entry,
        TECOMAT_POINTS,
        "fx2_cp2080",
        "BOOL",
        "INT",
        ("plcData.varReal", "REAL"),
        ("plcData.varBool0", "BOOL"),
        [(f"arr2[{i // 4}][{i % 4}]", "REAL") for i in range(10)],
        _by_path_read,
        _by_path_write,
        "PutObject",
        {
            "open": "Shutter.open",
            "close": "Shutter.close",
            "stop": "Pump.start",
            "open_limit": "Shutter.opened",
            "closed_limit": "Shutter.closed",
            "position": "plcData.varInt",
            "status": "plcData.varUint",
            "button": "Pump.run",
        },
    ),
    "plcnext": Family(
        "plcnext",
        PlcnextSimulator,
        _nothing,
        make_plcnext_entry,
        PLCNEXT_POINTS,
        "plcnext",
        "BOOL",
        "INT",
        (PLCNEXT_VARIABLES + "Setpoint", "REAL"),
        (PLCNEXT_VARIABLES + "Pump", "BOOL"),
        [(f"{PLCNEXT_VARIABLES}Levels[{i}]", "INT") for i in range(1, 5)]
        + [
            (PLCNEXT_VARIABLES + name, kind)
            for name, kind in (
                ("Speed", "INT"),
                ("Small", "SINT"),
                ("Tiny", "USINT"),
                ("Wide", "UINT"),
                ("Energy", "UDINT"),
                ("Total", "LINT"),
            )
        ],
        _by_path_read,
        _by_path_write,
        "PUT variables",
    ),
    "softplc": Family(
        "softplc",
        lambda: SoftplcSimulator(tls=True, put_auth=True),
        _nothing,
        _softplc_entry,
        SOFTPLC_POINTS,
        "softplc",
        "BOOL",
        "INT",
        ("F8:1", "REAL"),
        ("B3:0/5", "BOOL"),
        [(f"N7:{i}", "INT") for i in range(10)],
        _softplc_read,
        _softplc_write,
        None,
    ),
    "s7": Family(
        "s7",
        S7Simulator,
        fill,
        make_s7_entry,
        S7_POINTS,
        "s7_300",
        "BOOL",
        "INT",
        ("DB1.DBD200", "REAL"),
        ("M10.0", "BOOL"),
        [(f"DB1.DBW{100 + 2 * i}", "INT") for i in range(10)],
        _snap7_read,
        _snap7_write,
        "write",
    ),
    "logo": Family(
        "logo",
        lambda: LogoSimulator(LOGO_GENERATION),
        fill_logo,
        make_logo_entry,
        LOGO_POINTS,
        "logo",
        "BOOL",
        "INT",
        ("VD200", "REAL"),
        ("V12.0", "BOOL"),
        [(f"VW{100 + 2 * i}", "INT") for i in range(10)],
        _snap7_read,
        _snap7_write,
        "write",
    ),
}
"""The six PLC families of the Home Assistant tests, by vendor key."""


@dataclass
class PlcUnderTest:
    """One family's started simulator, as the Home Assistant tests meet it."""

    family: Family
    sim: Any

    @property
    def vendor(self) -> str:
        """The family's vendor key."""
        return self.family.key

    @property
    def bit(self) -> str:
        """The data type of a bit."""
        return self.family.bit

    @property
    def word(self) -> str:
        """The data type of a whole number."""
        return self.family.word

    @property
    def addresses(self) -> dict[str, str]:
        """The addresses of the output tests' roles (a cover's parts, a button)."""
        return self.family.roles

    def entry(
        self, hass: HomeAssistant, points: Iterable[PointData] | None = None
    ) -> MockConfigEntry:
        """Add the PLC's entry, as its flow stores it, with a machine of these points."""
        return self.family.entry(hass, self.sim, self.family.points if points is None else points)

    async def set_up(
        self, hass: HomeAssistant, points: Iterable[PointData] | None = None
    ) -> MockConfigEntry:
        """Add and set up the PLC's entry with these points (the family's own by default)."""
        return await set_up(hass, self.entry(hass, points))

    def read(self, address: str, data_type: str) -> Any:
        """Return what the simulator holds at an address."""
        return self.family.read(self.sim, address, data_type)

    def write(self, address: str, value: Any, data_type: str) -> None:
        """Set what the simulator holds at an address (the PLC's program did)."""
        self.family.write(self.sim, address, value, data_type)

    def requests(self) -> int:
        """Return the requests the simulator has served."""
        return int(self.sim.requests)

    def writes(self) -> int:
        """Return the write requests the simulator has served (SoftPLC: every request)."""
        if self.family.write_call is None:
            return self.requests()
        return int(self.sim.calls.get(self.family.write_call, 0))

    def entity(self, platform: str, name: str = "shutter") -> str:
        """Return the entity id of an entity of the PLC's machine."""
        return f"{platform}.{self.family.prefix}_{name}"

    def get(self, role: str) -> Any:
        """Return what the PLC holds at a role's address (bits as bool)."""
        kind = self.word if role in ("position", "status") else self.bit
        value = self.read(self.addresses[role], kind)
        return bool(value) if role not in ("position", "status") else value

    def set(self, role: str, value: Any) -> None:
        """Set what the PLC holds at a role's address (the program or the machine did)."""
        kind = self.word if role in ("position", "status") else self.bit
        self.write(self.addresses[role], value, kind)

    def part(
        self, role: str, name: str = "Shutter", platform: str = "cover", **extra: Any
    ) -> PointData:
        """Return a part of the test cover (or another entity) at the role's address."""
        kind = self.word if role in ("position", "status") else self.bit
        read_only = role in ("open_limit", "closed_limit", "status")
        data = {"role": role, "read_only": read_only} | extra
        return point(f"{name}_{role}".lower(), name, platform, self.addresses[role], kind, **data)


@asynccontextmanager
async def started(hass: HomeAssistant, key: str) -> AsyncIterator[PlcUnderTest]:
    """Start a family's simulator with its values; afterwards unload every entry and stop it."""
    family = FAMILIES[key]
    async with serving(hass, family.simulator()) as sim:
        family.fill(sim)
        yield PlcUnderTest(family, sim)
    if key in ("s7", "logo"):
        no_snap7_thread_left()


@pytest.fixture
async def plc(
    request: pytest.FixtureRequest, hass: HomeAssistant, freezer: FrozenDateTimeFactory
) -> AsyncGenerator[PlcUnderTest]:
    """The PLC of the family a test names (indirect parametrisation; else an S7-200 SMART).

    Time is frozen from before its entry is set up until every entry is unloaded.
    """
    async with started(hass, getattr(request, "param", "s7_smart")) as under_test:
        yield under_test


@pytest.fixture(params=list(FAMILIES))
async def every_plc(
    request: pytest.FixtureRequest, hass: HomeAssistant, freezer: FrozenDateTimeFactory
) -> AsyncGenerator[PlcUnderTest]:
    """The PLC of each of the six families, in turn (time frozen as for `plc`)."""
    async with started(hass, request.param) as under_test:
        yield under_test


# Exposes: Home Assistant states written to a PLC


def shown(plc: PlcUnderTest) -> PointData:
    """Return a sensor point polling the PLC's REAL target (it shows what exposes write)."""
    return point("shown", "Shown", "sensor", plc.family.real[0], plc.family.real[1])


def expose_data(entity_id: str, target: Target, **settings: Any) -> dict[str, Any]:
    """Return an expose's subentry data, as its form stores it (send-on-start off)."""
    data: dict[str, Any] = {
        CONF_ENTITY_ID: entity_id,
        CONF_ADDRESS: target[0],
        CONF_DATA_TYPE: target[1],
        CONF_SCALE: 1.0,
        CONF_OFFSET: 0.0,
        CONF_COOLDOWN: 1.0,
        CONF_RESEND: 0.0,
        CONF_SEND_ON_START: False,
    }
    for key in (CONF_ATTRIBUTE, CONF_VALUE_MAP, CONF_DEFAULT):
        if key in settings:
            data[key] = settings.pop(key)
    return data | settings


def add_expose(
    hass: HomeAssistant, entry: MockConfigEntry, entity_id: str, target: Target, **settings: Any
) -> str:
    """Add an expose subentry to an entry (loaded or not); return its subentry id."""
    subentry = ConfigSubentry(
        data=expose_data(entity_id, target, **settings),
        subentry_type=SUBENTRY_EXPOSE,
        title=f"{entity_id} → {target[0]}",
        unique_id=None,
    )
    hass.config_entries.async_add_subentry(entry, subentry)
    return subentry.subentry_id


async def settle(hass: HomeAssistant, freezer: FrozenDateTimeFactory, seconds: float = 0) -> None:
    """Let `seconds` pass (and the batch window), then wait for the writes that became due.

    Time is fired twice: a cooldown that ends puts its value into a batch, written a window on.
    """
    await hass.async_block_till_done()
    for _ in range(2):
        freezer.tick(timedelta(seconds=seconds + BATCH_WINDOW))
        async_fire_time_changed(hass)
        await hass.async_block_till_done(wait_background_tasks=True)
        seconds = 0


@dataclass(frozen=True, slots=True)
class Burst:
    """What changing every exposed entity at once cost, and what the PLC then held."""

    writes: int  # write requests the simulator served
    requests: int  # every request the client made (a read-back too)
    sent: list[int]  # the value each burst address was sent, in burst order
    held: list[Any]  # what each burst address holds afterwards


async def burst(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, plc: PlcUnderTest
) -> tuple[MockConfigEntry, Burst]:
    """Expose one entity to each burst address, set up, change them all at once; count."""
    targets = plc.family.burst
    entities = [f"input_number.level_{index}" for index in range(len(targets))]
    for entity_id in entities:
        hass.states.async_set(entity_id, "0")
    entry = plc.entry(hass, [shown(plc)])
    for entity_id, target in zip(entities, targets, strict=True):
        add_expose(hass, entry, entity_id, target)
    await set_up(hass, entry)
    client = entry.runtime_data.client
    writes, requests = plc.writes(), client.metrics.requests
    sent = [index % 100 + 11 for index in range(len(entities))]
    for entity_id, value in zip(entities, sent, strict=True):
        hass.states.async_set(entity_id, str(value))
    await settle(hass, freezer)
    return entry, Burst(
        writes=plc.writes() - writes,
        requests=client.metrics.requests - requests,
        sent=sent,
        held=[plc.read(*target) for target in targets],
    )


# Faults of writes

FAULTS = {
    "lost_answer": "the write lands, its answer is lost (a timeout)",
    "dropped": "the connection drops before the write lands",
}


@dataclass
class Faults:
    """Faults injected into the entry's client writes, and what every write carried."""

    plc: PlcUnderTest
    queue: list[str] = field(default_factory=list)
    writes: list[tuple[dict[str, Any], bool]] = field(default_factory=list)
    both: list[int] = field(default_factory=list)  # writes after which open and close were on

    def wrap(self, client: Any, monkeypatch: pytest.MonkeyPatch) -> None:
        """Route the client's writes through the fault queue."""
        original = client.write

        async def write(values: Any) -> Any:
            self.writes.append(({p.address: v for p, v in values.items()}, URGENT.get()))
            fault = self.queue.pop(0) if self.queue else None
            if fault == "dropped":
                raise PlcConnectionError("the connection was reset")
            try:
                return await original(values)
            finally:
                if self.plc.get("open") and self.plc.get("close"):
                    self.both.append(len(self.writes))
                if fault == "lost_answer":
                    raise PlcTimeoutError("the PLC did not answer in time")

        monkeypatch.setattr(client, "write", write)

    def sent(self, role: str) -> list[Any]:
        """The values written to a role's address, in order."""
        address = self.plc.addresses[role]
        return [values[address] for values, _ in self.writes if address in values]


@pytest.fixture
def faults(plc: PlcUnderTest) -> Faults:
    """The fault queue of the test PLC (wrap it once the entry is set up)."""
    return Faults(plc)


async def wait(hass: HomeAssistant, freezer: FrozenDateTimeFactory, seconds: float) -> None:
    """Let time pass and the timers and tasks due run."""
    freezer.tick(timedelta(seconds=seconds))
    async_fire_time_changed(hass)
    await hass.async_block_till_done(wait_background_tasks=True)


OUTPUT_FAMILIES = ("s7_smart", "tecomat")
"""The families the output tests (covers' level commands, pulses) run on."""


@pytest.fixture
def outputs_at_rest(plc: PlcUnderTest) -> None:
    """Start the output tests' position and status words at 0 (a TecoApi program ships others)."""
    plc.set("position", 0)
    plc.set("status", 0)
