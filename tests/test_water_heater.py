"""Water heaters of several addresses, built as a user builds them, on every simulator.

The kind is its description (model/kinds.py), its platform module and its strings: the device
flow's composite steps, the table import and the pasted file make it like any other kind.
"""

from __future__ import annotations

from collections.abc import AsyncGenerator, Callable
from dataclasses import dataclass
import threading
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.components.water_heater import (  # type: ignore[attr-defined]
    ATTR_CURRENT_TEMPERATURE,
    ATTR_MAX_TEMP,
    ATTR_MIN_TEMP,
    ATTR_OPERATION_LIST,
    ATTR_OPERATION_MODE,
    ATTR_TARGET_TEMP_STEP,
    DOMAIN as WATER_HEATER_DOMAIN,
    SERVICE_SET_OPERATION_MODE,
    SERVICE_SET_TEMPERATURE,
)
from homeassistant.config_entries import SOURCE_RECONFIGURE, SOURCE_USER
from homeassistant.const import (
    ATTR_ENTITY_ID,
    ATTR_TEMPERATURE,
    CONF_PASSWORD,
    SERVICE_TURN_OFF,
    SERVICE_TURN_ON,
    STATE_OFF,
)
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.exceptions import ServiceValidationError
from homeassistant.helpers import entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import CONF_OPTIONS, CONF_POINTS, SUBENTRY_DEVICE
from custom_components.plc_bridge.plc.vendors.logo.options import DEFAULT_TSAPS
from simulators.logo import LogoSimulator
from simulators.s7_smart import DEFAULT_PASSWORD as SMART_PASSWORD
from tests.entries import (
    DEVICE_ID,
    add_entry,
    entry_data,
    make_entry,
    point,
    read_edits,
    set_up as set_up_entry,
    unload_all,
)
from tests.flows.forms import entity_page, on_page, step
from tests.harness import (
    SNAP7_THREADS,
    make_plcnext_entry,
    make_s7_entry,
    make_softplc_entry,
    make_tecomat_entry,
)
from tests.loopback import running
from tests.test_config_file import confirm, export, paste

pytestmark = pytest.mark.no_pacing

MODES = "0=off;1=eco;2=performance"
ROLES = ("current_temperature", "target_temperature", "operation_mode", "on_off")


def _word(db: int, offset: int) -> tuple[Callable[..., None], Callable[..., Any]]:
    """Return how to put and take a big-endian INT at a data block offset (S7 and LOGO! VM)."""

    def put(sim: Any, value: int) -> None:
        """Store the word."""
        sim.set_db(db, offset, int(value).to_bytes(2, "big", signed=True))

    def take(sim: Any) -> int:
        """Read the word."""
        return int.from_bytes(sim.get_db(db, offset, 2), "big", signed=True)

    return put, take


def _bit(db: int, offset: int) -> tuple[Callable[..., None], Callable[..., Any]]:
    """Return how to put and take bit 0 of a data block byte."""

    def put(sim: Any, value: bool) -> None:
        """Set or clear the bit (the byte's other bits are 0 here)."""
        sim.set_db(db, offset, b"\x01" if value else b"\x00")

    def take(sim: Any) -> bool:
        """Read the bit."""
        return bool(sim.get_db(db, offset, 1)[0] & 1)

    return put, take


def _named(path: str) -> tuple[Callable[..., None], Callable[..., Any]]:
    """Return how to put and take a value by the simulator's own get and set."""
    return (lambda sim, value: sim.set(path, value)), (lambda sim: sim.get(path))


def _softplc(file: str, number: int, word: int, bit: int | None = None) -> Any:
    """Return how to put and take a SoftPLC datatable word, or one bit of it."""

    def put(sim: Any, value: Any) -> None:
        """Store the word (or the bit)."""
        words = sim.files[file, number].words
        if bit is None:
            words[word] = int(value)
        else:
            words[word] = (words[word] & ~(1 << bit)) | (int(bool(value)) << bit)

    def take(sim: Any) -> Any:
        """Read the word (or the bit)."""
        value = sim.files[file, number].words[word]
        return value if bit is None else bool(value >> bit & 1)

    return put, take


@dataclass(frozen=True, slots=True)
class Rig:
    """A vendor's simulator and where a water heater's parts are in it."""

    sim: str
    """The fixture of the started simulator."""
    entry: Callable[[HomeAssistant, Any], MockConfigEntry]
    """Adds the simulator's entry without machines (not set up)."""
    parts: dict[str, tuple[str, str, Any]]
    """By role: the address and data type typed in the form, and how to put and take its raw."""


def _s7_smart(hass: HomeAssistant, sim: Any) -> MockConfigEntry:
    """An S7-200 SMART entry without machines."""
    return make_entry(hass, sim, [])


def _softplc_entry(hass: HomeAssistant, sim: Any) -> MockConfigEntry:
    """A SoftPLC entry, its client certificate trusted for writes."""
    cert, key = sim.client_certificate(trusted=True)
    options = {CONF_OPTIONS: {"client_certificate": cert, "client_key": key}}
    return make_softplc_entry(hass, sim, [], **options)


def _logo(hass: HomeAssistant, sim: LogoSimulator) -> MockConfigEntry:
    """A LOGO! 8 entry (default TSAPs) without machines."""
    local, remote = DEFAULT_TSAPS[sim.generation]
    options = {"generation": sim.generation, "local_tsap": local, "remote_tsap": remote}
    return add_entry(
        hass,
        title="LOGO",
        entry_id="01JPLCBR1DGE0000000LOGO8X",
        unique_id=f"{sim.host}:{sim.port}",
        data=entry_data("logo", sim, ("", ""), options=options),
    )


MAIN = "Arp.Plc.Eclr/MainInstance."
RIGS = {
    "s7_smart": Rig(
        "s7_smart_ha_sim",
        _s7_smart,
        {
            "current_temperature": ("VW50", "signed", _named("VW50")),
            "target_temperature": ("VW52", "signed", _named("VW52")),
            "operation_mode": ("VW54", "signed", _named("VW54")),
            "on_off": ("Q0.7", "", _named("Q0.7")),
        },
    ),
    "tecomat": Rig(
        "tecomat_ha_sim",
        lambda hass, sim: make_tecomat_entry(hass, sim, []),
        {
            "current_temperature": ("plcData.varInt", "INT", _named("plcData.varInt")),
            "target_temperature": ("plcData.varUint", "UINT", _named("plcData.varUint")),
            "operation_mode": ("plcData.varUsint", "USINT", _named("plcData.varUsint")),
            "on_off": ("plcData.varBool0", "BOOL", _named("plcData.varBool0")),
        },
    ),
    "plcnext": Rig(
        "plcnext_ha_sim",
        lambda hass, sim: make_plcnext_entry(hass, sim, []),
        {
            "current_temperature": (MAIN + "Speed", "INT", _named("MainInstance.Speed")),
            "target_temperature": (MAIN + "Wide", "UINT", _named("MainInstance.Wide")),
            "operation_mode": (MAIN + "Tiny", "USINT", _named("MainInstance.Tiny")),
            "on_off": (MAIN + "Pump", "BOOL", _named("MainInstance.Pump")),
        },
    ),
    "softplc": Rig(
        "softplc_ha_sim",
        _softplc_entry,
        {
            "current_temperature": ("N7:1", "INT", _softplc("N", 7, 1)),
            "target_temperature": ("N7:2", "INT", _softplc("N", 7, 2)),
            "operation_mode": ("N7:3", "INT", _softplc("N", 7, 3)),
            "on_off": ("B3:1/0", "BOOL", _softplc("B", 3, 1, 0)),
        },
    ),
    "s7": Rig(
        "s7_ha_sim",
        lambda hass, sim: make_s7_entry(hass, sim, []),
        {
            "current_temperature": ("DB1.DBW200", "INT", _word(1, 200)),
            "target_temperature": ("DB1.DBW202", "INT", _word(1, 202)),
            "operation_mode": ("DB1.DBW204", "INT", _word(1, 204)),
            "on_off": ("DB1.DBX206.0", "BOOL", _bit(1, 206)),
        },
    ),
    "logo": Rig(
        "logo_sim",
        _logo,
        {
            "current_temperature": ("VW200", "INT", _word(1, 200)),
            "target_temperature": ("VW202", "INT", _word(1, 202)),
            "operation_mode": ("VW204", "INT", _word(1, 204)),
            "on_off": ("V206.0", "BOOL", _bit(1, 206)),
        },
    ),
}
"""Every simulator that can hold a water heater: two words, a small integer and a bit."""

PAGE_SETTINGS = {
    "scale": 0.1,
    "offset": 0,
    "min": 30,
    "max": 70,
    "step": 0.5,
    "operation_mode_value_map": MODES,
}
"""What the user fills in on the page besides addresses (temperatures in tenths, asked once)."""


@pytest.fixture
async def logo_sim(hass: HomeAssistant) -> AsyncGenerator[LogoSimulator]:
    """A started LOGO! 8 simulator; its entries unloaded and its threads gone afterwards."""
    sim = LogoSimulator("8_x")
    async with running(sim):
        yield sim
        await unload_all(hass)
    lingering = [t.name for t in threading.enumerate() if t.name.endswith(SNAP7_THREADS)]
    assert not lingering, f"snap7 server threads left running: {lingering}"


@pytest.fixture
def rig_sim(request: pytest.FixtureRequest) -> tuple[Rig, Any]:
    """The vendor the test is parametrized with, and its started simulator."""
    rig = RIGS[request.param]
    return rig, request.getfixturevalue(rig.sim)


def put(rig: Rig, sim: Any, role: str, value: Any) -> None:
    """Store a part's raw value in the simulator."""
    rig.parts[role][2][0](sim, value)


def take(rig: Rig, sim: Any, role: str) -> Any:
    """Read a part's raw value from the simulator."""
    return rig.parts[role][2][1](sim)


def heater_id(hass: HomeAssistant, entry: MockConfigEntry) -> str:
    """Return the entity id of the entry's one water heater."""
    (found,) = [
        registered.entity_id
        for registered in er.async_entries_for_config_entry(er.async_get(hass), entry.entry_id)
        if registered.domain == WATER_HEATER_DOMAIN
    ]
    return found


async def build(hass: HomeAssistant, entry: MockConfigEntry, rig: Rig) -> None:
    """Add a machine holding a water heater through the device flow, as a user does."""
    menu = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_DEVICE), context={"source": SOURCE_USER}
    )
    menu = await step(hass, menu, {"name": "Boiler room"})
    result = await entity_page(hass, menu, "water_heater")
    assert result["step_id"] == "composite_entity"
    given: dict[str, Any] = {"name": "Tank", **PAGE_SETTINGS}
    for role, (address, data_type, _) in rig.parts.items():
        given[role] = address
        if data_type:
            given[f"{role}_data_type"] = data_type
    result = await step(hass, result, on_page("water_heater", given))
    assert result["type"] is FlowResultType.MENU, result.get("errors")
    result = await step(hass, result, {"next_step_id": "save"})
    assert result["type"] is FlowResultType.CREATE_ENTRY


async def call(hass: HomeAssistant, entity_id: str, service: str, **data: Any) -> None:
    """Call a water heater action."""
    await hass.services.async_call(
        WATER_HEATER_DOMAIN, service, {ATTR_ENTITY_ID: entity_id, **data}, blocking=True
    )


async def drive(hass: HomeAssistant, entity_id: str, rig: Rig, sim: Any) -> None:
    """Check the state shown, then set the temperature, the mode, off and on again."""
    state = hass.states.get(entity_id)
    assert state.state == "eco"
    assert state.attributes[ATTR_CURRENT_TEMPERATURE] == 21.5
    assert state.attributes[ATTR_TEMPERATURE] == 50
    assert state.attributes[ATTR_OPERATION_LIST] == ["off", "eco", "performance"]
    assert (state.attributes[ATTR_MIN_TEMP], state.attributes[ATTR_MAX_TEMP]) == (30, 70)
    assert state.attributes[ATTR_TARGET_TEMP_STEP] == 0.5
    await call(hass, entity_id, SERVICE_SET_TEMPERATURE, **{ATTR_TEMPERATURE: 55.5})
    assert take(rig, sim, "target_temperature") == 555
    with pytest.raises(ServiceValidationError):
        await call(hass, entity_id, SERVICE_SET_TEMPERATURE, **{ATTR_TEMPERATURE: 90})
    assert take(rig, sim, "target_temperature") == 555
    await call(hass, entity_id, SERVICE_SET_OPERATION_MODE, **{ATTR_OPERATION_MODE: "performance"})
    assert take(rig, sim, "operation_mode") == 2
    assert hass.states.get(entity_id).state == "performance"
    await call(hass, entity_id, SERVICE_TURN_OFF)
    assert not take(rig, sim, "on_off")
    assert take(rig, sim, "operation_mode") == 2  # the mode is kept while off
    assert hass.states.get(entity_id).state == STATE_OFF
    await call(hass, entity_id, SERVICE_TURN_ON)
    assert take(rig, sim, "on_off")
    assert hass.states.get(entity_id).state == "performance"
    await call(hass, entity_id, SERVICE_SET_OPERATION_MODE, **{ATTR_OPERATION_MODE: STATE_OFF})
    assert not take(rig, sim, "on_off")
    assert take(rig, sim, "operation_mode") == 2  # off by the on/off part, not the map's 0


def heating(rig: Rig, sim: Any) -> None:
    """Put a tank at 21.5 °C, set to 50 °C, in eco mode and on into the simulator."""
    for role, value in (
        ("current_temperature", 215),
        ("target_temperature", 500),
        ("operation_mode", 1),
        ("on_off", True),
    ):
        put(rig, sim, role, value)


@pytest.mark.parametrize("rig_sim", RIGS, indirect=True)
async def test_built_in_the_flow(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, rig_sim: tuple[Rig, Any]
) -> None:
    """Built from the machine's menu like a cover or climate; read and written on every PLC."""
    rig, sim = rig_sim
    heating(rig, sim)
    entry = await set_up_entry(hass, rig.entry(hass, sim))
    await build(hass, entry, rig)
    await read_edits(hass, freezer)
    (machine,) = entry.subentries.values()
    parts = {data["role"]: data for data in machine.data[CONF_POINTS].values()}
    assert set(parts) == set(ROLES)
    assert {data["platform"] for data in parts.values()} == {"water_heater"}
    await drive(hass, heater_id(hass, entry), rig, sim)


TABLE = """name,address,data_type,platform,scale,min,max,step,read_only,value_map,role
Tank,VW50,signed,water_heater,0.1,,,,yes,,current_temperature
Tank,VW52,signed,water_heater,0.1,30,70,0.5,no,,target_temperature
Tank,VW54,signed,water_heater,1,,,,no,0=off;1=eco;2=performance,operation_mode
Tank,Q0.7,,water_heater,1,,,,no,,on_off
"""


async def test_imported_as_a_table(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, s7_smart_ha_sim: Any
) -> None:
    """The same water heater pasted as table rows: one row per part, each naming its role."""
    rig = RIGS["s7_smart"]
    heating(rig, s7_smart_ha_sim)
    entry = await set_up_entry(
        hass, make_entry(hass, s7_smart_ha_sim, [point("x", "X", "sensor", "VW0", "signed")])
    )
    menu = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_DEVICE),
        context={"source": SOURCE_RECONFIGURE, "subentry_id": DEVICE_ID},
    )
    result = await step(hass, menu, {"next_step_id": "import_points"})
    result = await step(hass, result, {"table": TABLE})
    assert result["type"] is FlowResultType.MENU, result.get("description_placeholders")
    result = await step(hass, result, {"next_step_id": "save"})
    await read_edits(hass, freezer)
    await drive(hass, heater_id(hass, entry), rig, s7_smart_ha_sim)


TANK = [
    point(
        "w1",
        "Tank",
        "water_heater",
        "VW50",
        "signed",
        role="current_temperature",
        scale=0.1,
        read_only=True,
    ),
    point(
        "w2",
        "Tank",
        "water_heater",
        "VW52",
        "signed",
        role="target_temperature",
        scale=0.1,
        min=30.0,
        max=70.0,
        step=0.5,
    ),
    point("w3", "Tank", "water_heater", "VW54", "signed", role="operation_mode", value_map=MODES),
    point("w4", "Tank", "water_heater", "Q0.7", "signed", role="on_off"),
]


async def test_pasted_file(hass: HomeAssistant, s7_smart_ha_sim: Any) -> None:
    """Exported, removed and pasted back: the same water heater, driven the same way."""
    rig = RIGS["s7_smart"]
    heating(rig, s7_smart_ha_sim)
    entry = await set_up_entry(hass, make_entry(hass, s7_smart_ha_sim, TANK))
    before = heater_id(hass, entry)
    text = await export(hass, entry)
    assert "water_heater" in text
    assert await hass.config_entries.async_remove(entry.entry_id)
    await hass.async_block_till_done()
    result = await confirm(hass, await paste(hass, text), {CONF_PASSWORD: SMART_PASSWORD})
    assert result["type"] is FlowResultType.CREATE_ENTRY, result.get("errors")
    await hass.async_block_till_done()
    new = result["result"]
    assert heater_id(hass, new) == before
    await drive(hass, before, rig, s7_smart_ha_sim)
