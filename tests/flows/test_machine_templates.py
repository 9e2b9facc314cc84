"""Machines made from one (issue 26 item 3): twelve shutters from one, on every simulator.

One flow from Shutter 1's menu makes Shutter 2 to Shutter 12, each its own device with its own
cover (three parts) and fault sensor (slow poll class) and its own data-valid address, all
moved by the vendor; a poll of the twelve costs the PLC what twelve machines made by hand do.
A stride that runs out of the area or overlaps is refused with nothing made; the PLC file
keeps the template and its copies and makes the copies it names but lacks.
"""

from __future__ import annotations

from collections.abc import AsyncIterator, Callable
from contextlib import asynccontextmanager
from dataclasses import dataclass, field
import threading
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import ConfigSubentryDataWithId
from homeassistant.const import CONF_NAME
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import device_registry as dr, entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import (
    CONF_ADDRESS,
    CONF_POINTS,
    CONF_ROLE,
    SUBENTRY_DEVICE,
)
from custom_components.plc_bridge.model.availability import CONF_AVAILABILITY_ADDRESS
from custom_components.plc_bridge.model.config_file import (
    ConfigFileError,
    dump_config,
    load_config,
)
from custom_components.plc_bridge.model.template import CONF_COPY_OF, CONF_TEMPLATE
from custom_components.plc_bridge.plc.vendors.logo.options import DEFAULT_TSAPS
from simulators.logo import LogoSimulator
from simulators.plcnext import PlcnextSimulator
from simulators.plcnext.program import PREFIX as PLCNEXT_PREFIX, Array, Leaf, Program, Variable
from simulators.s7 import S7Simulator
from simulators.s7_smart import S7SmartSimulator
from simulators.softplc import SoftplcSimulator
from simulators.tecomat import TecomatSimulator
from simulators.tecomat.values import Var
from tests.entries import (
    add_entry,
    device,
    entry_data,
    point,
    poll,
    read_edits,
    sim_data,
    unload_all,
)
from tests.flows.forms import MACHINE, error_message, step
from tests.harness import SNAP7_THREADS, plcnext_data, s7_data, softplc_data, tecomat_data
from tests.loopback import running
from tests.test_config_file import confirm, export, paste

pytestmark = pytest.mark.no_pacing

COPIES = 11
"""Copies made of Shutter 1: twelve shutters in all."""
RANGE = {"raw_min": 0, "raw_max": 100, "shown_min": 0, "shown_max": 100}


@dataclass(frozen=True, slots=True)
class Plant:
    """A vendor's shutter: its addresses for shutter n, data types, and how the form moves it."""

    vendor: str
    addresses: Callable[[int], tuple[str, str, str, str, str]]  # position, up, down, fault, valid
    types: tuple[str, str]  # a word's and a bit's data type
    form: dict[str, Any] = field(default_factory=dict)


PLANTS = {
    "s7_smart": Plant(
        "s7_smart",
        lambda n: (
            f"VW{100 + 20 * (n - 1)}",
            f"V{102 + 20 * (n - 1)}.0",
            f"V{102 + 20 * (n - 1)}.1",
            f"V{103 + 20 * (n - 1)}.0",
            f"V{104 + 20 * (n - 1)}.0",
        ),
        ("signed", "signed"),
        {"unit": "bytes", "stride": 20},
    ),
    "s7": Plant(
        "s7",
        lambda n: (
            f"DB10.DBW{24 * (n - 1)}",
            f"DB10.DBX{24 * (n - 1) + 2}.0",
            f"DB10.DBX{24 * (n - 1) + 2}.1",
            f"DB10.DBX{24 * (n - 1) + 3}.0",
            f"DB10.DBX{24 * (n - 1) + 4}.0",
        ),
        ("INT", "BOOL"),
        {"unit": "bytes", "stride": 24},
    ),
    "logo": Plant(
        "logo",
        lambda n: (
            f"VW{100 + 24 * (n - 1)}",
            f"V{102 + 24 * (n - 1)}.0",
            f"V{102 + 24 * (n - 1)}.1",
            f"V{103 + 24 * (n - 1)}.0",
            f"V{104 + 24 * (n - 1)}.0",
        ),
        ("INT", "BOOL"),
        {"unit": "bytes", "stride": 24},
    ),
    "softplc": Plant(
        "softplc",
        lambda n: (
            f"N7:{10 + 5 * (n - 1)}",
            f"N7:{11 + 5 * (n - 1)}/0",
            f"N7:{11 + 5 * (n - 1)}/1",
            f"N7:{12 + 5 * (n - 1)}/0",
            f"N7:{13 + 5 * (n - 1)}/0",
        ),
        ("INT", "BOOL"),
        {"unit": "elements", "stride": 5},
    ),
    "tecomat": Plant(
        "tecomat",
        lambda n: (
            f"Shutter_{n}.Position",
            f"Shutter_{n}.Up",
            f"Shutter_{n}.Down",
            f"Shutter_{n}.Fault",
            f"Shutter_{n}.Valid",
        ),
        ("INT", "BOOL"),
        {"part": "Shutter_1.", "stride": 1},
    ),
    "plcnext": Plant(
        "plcnext",
        lambda n: tuple(  # type: ignore[return-value]
            f"{PLCNEXT_PREFIX}HomeInstance.Shutter[{n}].{member}"
            for member in ("Position", "Up", "Down", "Fault", "Valid")
        ),
        ("INT", "BOOL"),
        {"part": "HomeInstance.Shutter[1].", "stride": 1},
    ),
}


def shutter(plant: Plant, n: int, prefix: str = "") -> ConfigSubentryDataWithId:
    """Return shutter n as a hand would make it: a cover of three parts, a fault sensor."""
    position, up, down, fault, valid = plant.addresses(n)
    word, bit = plant.types
    points = [
        point(f"{prefix}p{n}", "Shutter", "cover", position, word, role="position", **RANGE),
        point(f"{prefix}u{n}", "Shutter", "cover", up, bit, role="open"),
        point(f"{prefix}d{n}", "Shutter", "cover", down, bit, role="close"),
        point(f"{prefix}f{n}", "Fault", "binary_sensor", fault, bit, poll="slow"),
    ]
    made = device(points, f"{prefix}shutter{n}", f"Shutter {n}")
    made["data"] = {
        **made["data"],
        CONF_AVAILABILITY_ADDRESS: valid,
        "availability_data_type": bit,
    }
    for data in made["data"][CONF_POINTS].values():
        if data.get(CONF_ROLE):
            data["entity"] = f"{prefix}p{n}"
    return made


@asynccontextmanager
async def simulator(hass: HomeAssistant, vendor: str) -> AsyncIterator[Any]:
    """Start the vendor's simulator holding twelve shutters; unload and stop it afterwards."""
    sim: Any
    if vendor == "s7_smart":
        sim = S7SmartSimulator()
    elif vendor == "s7":
        sim = S7Simulator(dbs={1: 64, 10: 512})
    elif vendor == "logo":
        sim = LogoSimulator("0ba8")
    elif vendor == "softplc":
        sim = SoftplcSimulator(bench=0)
    elif vendor == "tecomat":
        sim = TecomatSimulator(bench=0)
        for n in range(1, 13):
            sim.variables[f"Shutter_{n}"] = {
                "Position": Var("INT", 10 * n),
                **{name: Var("BOOL", False) for name in ("Up", "Down", "Fault")},
                "Valid": Var("BOOL", True),
            }
    else:
        sim = PlcnextSimulator()
        members: list[Any] = [
            {
                "Position": Leaf("INT", 10 * n),
                **{name: Leaf("BOOL", False) for name in ("Up", "Down", "Fault")},
                "Valid": Leaf("BOOL", True),
            }
            for n in range(1, 13)
        ]
        shutters = Array("ShutterArray", "ShutterType", ((1, 12),), members)
        name = PLCNEXT_PREFIX + "HomeInstance.Shutter"
        sim.program = Program({**sim.program.variables, name: Variable("ShutterArray", shutters)})
    async with running(sim):
        try:
            yield sim
        finally:
            await unload_all(hass)
    lingering = [t.name for t in threading.enumerate() if t.name.endswith(SNAP7_THREADS)]
    assert not lingering, f"snap7 server threads left running: {lingering}"


def plc_data(vendor: str, sim: Any) -> dict[str, Any]:
    """Return the entry data the config flow stores for the vendor's simulator."""
    if vendor == "s7_smart":
        return sim_data(sim)
    if vendor == "s7":
        return s7_data(sim)
    if vendor == "logo":
        local, remote = DEFAULT_TSAPS["0ba8"]
        options = {"generation": "0ba8", "local_tsap": local, "remote_tsap": remote}
        return entry_data("logo", sim, ("", ""), options=options)
    if vendor == "softplc":
        return softplc_data(sim)
    if vendor == "tecomat":
        return tecomat_data(sim)
    return plcnext_data(sim)


async def plant_entry(
    hass: HomeAssistant, vendor: str, sim: Any, machines: list[ConfigSubentryDataWithId], key: str
) -> MockConfigEntry:
    """Add and set up an entry of the simulator holding the machines."""
    entry = add_entry(
        hass,
        title="Plant",
        entry_id=f"01JPLCBR1DGE00TEMPLATES{key:>3}",
        unique_id=f"plant-{key}",
        data=plc_data(vendor, sim),
        subentries=machines,
    )
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    return entry


async def open_copies(hass: HomeAssistant, entry: MockConfigEntry, subentry_id: str) -> Any:
    """Open a stored machine's menu and its "Add machines like this one" form."""
    result = await entry.start_subentry_reconfigure_flow(hass, subentry_id)
    assert result["type"] is FlowResultType.MENU
    assert "copies" in result["menu_options"]
    form = await step(hass, result, {"next_step_id": "copies"})
    assert form["type"] is FlowResultType.FORM
    return form


def machines(entry: MockConfigEntry) -> dict[str, dict[str, Any]]:
    """Return the entry's machines by title, as stored."""
    return {
        subentry.title: dict(subentry.data)
        for subentry in entry.subentries.values()
        if subentry.subentry_type == SUBENTRY_DEVICE
    }


def layout(data: dict[str, Any]) -> list[tuple[str, str, str]]:
    """Return a machine's points as (name, role, address), and its data-valid address."""
    rows = sorted(
        (str(p[CONF_NAME]), str(p.get(CONF_ROLE) or ""), str(p[CONF_ADDRESS]))
        for p in data[CONF_POINTS].values()
    )
    return [*rows, ("valid", "", str(data[CONF_AVAILABILITY_ADDRESS]))]


async def requests_per_poll(hass: HomeAssistant, freezer: FrozenDateTimeFactory, sim: Any) -> int:
    """Return the requests the simulator got over three polls, once the plan has settled."""
    await read_edits(hass, freezer)
    await poll(hass, freezer)
    before = sim.requests
    await poll(hass, freezer, 3)
    return int(sim.requests - before)


@pytest.mark.parametrize("vendor", list(PLANTS))
async def test_twelve_shutters_from_one(
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, vendor: str
) -> None:
    """One flow makes Shutter 2..12, poll cost as twelve made by hand."""
    plant = PLANTS[vendor]
    async with simulator(hass, vendor) as sim:
        entry = await plant_entry(hass, vendor, sim, [shutter(plant, 1)], "one")
        form = await open_copies(hass, entry, "shutter1")
        result = await step(hass, form, {"count": COPIES, "name": "Shutter {n}", **plant.form})
        assert result["type"] is FlowResultType.ABORT, result.get("errors")
        assert result["reason"] == "reconfigure_successful"
        await hass.async_block_till_done()

        made = machines(entry)
        assert sorted(made) == sorted(f"Shutter {n}" for n in range(1, 13))
        for n in range(1, 13):
            assert layout(made[f"Shutter {n}"]) == layout(shutter(plant, n)["data"]), n
            faults = [
                p for p in made[f"Shutter {n}"][CONF_POINTS].values() if p[CONF_NAME] == "Fault"
            ]
            assert [p.get("poll") for p in faults] == ["slow"]
        record = made["Shutter 1"][CONF_TEMPLATE]
        assert (record["count"], record["name"]) == (COPIES, "Shutter {n}")
        assert {made[f"Shutter {n}"][CONF_COPY_OF]["number"] for n in range(2, 13)} == set(
            range(2, 13)
        )

        registry = er.async_get(hass)
        entities = er.async_entries_for_config_entry(registry, entry.entry_id)
        shown = [e for e in entities if e.config_subentry_id in entry.subentries]
        assert len(shown) == 24
        assert len({e.unique_id for e in entities}) == len(entities)
        devices = dr.async_entries_for_config_entry(dr.async_get(hass), entry.entry_id)
        assert {d.name for d in devices} >= {f"Shutter {n}" for n in range(1, 13)}
        assert len({e.device_id for e in shown}) == 12

        copied = await requests_per_poll(hass, freezer, sim)
        await unload_all(hass)
        by_hand = [shutter(plant, n, "hand") for n in range(1, 13)]
        await plant_entry(hass, vendor, sim, by_hand, "hnd")
        assert copied > 0
        assert await requests_per_poll(hass, freezer, sim) == copied


@pytest.mark.parametrize(
    ("stride", "field", "words"),
    [
        (2000, "stride", "Machine 12 of the series cannot be made: VW22100 is outside V memory"),
        (2, "stride", "Machine 2 of the series cannot be made: VW102 of Shutter 2 overlaps V102.0"),
        (140, "stride", "Machine 3 of the series cannot be made: VW380 of Shutter 3 overlaps"),
    ],
)
async def test_stride_out_of_area_or_overlapping_refused(
    hass: HomeAssistant, stride: int, field: str, words: str
) -> None:
    """The first failing address is shown on the stride; nothing is made or changed."""
    plant = PLANTS["s7_smart"]
    pump = device([point("pump", "Pump", "sensor", "VW380", "signed")], "pump", "Pump")
    async with simulator(hass, "s7_smart") as sim:
        entry = await plant_entry(hass, "s7_smart", sim, [shutter(plant, 1), pump], "ref")
        before = machines(entry)
        form = await open_copies(hass, entry, "shutter1")
        values = {"count": COPIES, "name": "Shutter {n}", "unit": "bytes", "stride": stride}
        result = await step(hass, form, values)
        assert result["type"] is FlowResultType.FORM
        assert error_message(result, field, *MACHINE).startswith(words)
        assert machines(entry) == before


async def test_name_part_missing_and_name_pattern_refused(hass: HomeAssistant) -> None:
    """A part no variable holds is refused on the part; names need {n}, and a free name."""
    plant = PLANTS["tecomat"]
    async with simulator(hass, "tecomat") as sim:
        pump = device([point("pump", "Pump", "switch", "Main.pump", "BOOL")], "pump", "shutter 3")
        entry = await plant_entry(hass, "tecomat", sim, [shutter(plant, 1), pump], "nam")
        form = await open_copies(hass, entry, "shutter1")
        result = await step(
            hass, form, {"count": 2, "name": "Shutter {n}", "part": "Pump_1.", "stride": 1}
        )
        assert "Shutter_1.Position (Pump_1): the part that counts is not in this name" in (
            error_message(result, "part", *MACHINE)
        )
        result = await step(
            hass, result, {"count": 2, "name": "Shutter", "part": "Shutter_1.", "stride": 1}
        )
        assert error_message(result, "name", *MACHINE) == "the names need {n}"
        result = await step(
            hass, result, {"count": 2, "name": "Shutter {n}", "part": "Shutter_2.", "stride": 1}
        )
        assert "the part that counts is not in this name" in error_message(result, "part", *MACHINE)
        result = await step(
            hass, result, {"count": 2, "name": "Shutter {n}", "part": "Shutter_1.", "stride": 1}
        )
        assert error_message(result, "name", *MACHINE) == (
            "Machine 3 of the series cannot be made: another machine is named Shutter 3"
        )
        assert sorted(machines(entry)) == ["Shutter 1", "shutter 3"]


async def test_editing_the_original_keeps_copies_and_record(hass: HomeAssistant) -> None:
    """The original renamed later keeps its record; its copies keep their points."""
    plant = PLANTS["softplc"]
    async with simulator(hass, "softplc") as sim:
        entry = await plant_entry(hass, "softplc", sim, [shutter(plant, 1)], "edt")
        form = await open_copies(hass, entry, "shutter1")
        await step(hass, form, {"count": 2, "name": "Shutter {n}", "unit": "elements", "stride": 5})
        copies = {k: v for k, v in machines(entry).items() if k != "Shutter 1"}
        result = await entry.start_subentry_reconfigure_flow(hass, "shutter1")
        result = await step(hass, result, {"next_step_id": "device"})
        valid = {CONF_AVAILABILITY_ADDRESS: "N7:13/0", "availability_data_type": "BOOL"}
        result = await step(hass, result, {"name": "Living room shutter", **valid})
        result = await step(hass, result, {"next_step_id": "save"})
        assert result["reason"] == "reconfigure_successful"
        stored = machines(entry)
        assert stored["Living room shutter"][CONF_TEMPLATE]["count"] == 2
        assert {k: v for k, v in stored.items() if k != "Living room shutter"} == copies

        more = await open_copies(hass, entry, "shutter1")
        result = await step(hass, more, {"count": 1, "name": "Shutter {n}", "stride": 5})
        assert result["reason"] == "reconfigure_successful"
        assert machines(entry)["Shutter 4"][CONF_COPY_OF]["number"] == 4
        assert layout(machines(entry)["Shutter 4"]) == layout(shutter(plant, 4)["data"])


async def test_copy_menu_has_no_copies(hass: HomeAssistant) -> None:
    """A copy's menu does not offer copies of itself: they are made from the original."""
    plant = PLANTS["s7_smart"]
    async with simulator(hass, "s7_smart") as sim:
        entry = await plant_entry(hass, "s7_smart", sim, [shutter(plant, 1)], "cpy")
        form = await open_copies(hass, entry, "shutter1")
        await step(hass, form, {"count": 1, "name": "Shutter {n}", "unit": "bytes", "stride": 20})
        copy = next(s for s in entry.subentries.values() if s.title == "Shutter 2")
        result = await entry.start_subentry_reconfigure_flow(hass, copy.subentry_id)
        assert "copies" not in result["menu_options"]


async def test_export_and_paste_keep_template_and_copies(hass: HomeAssistant) -> None:
    """The file holds the record and every copy; a file without the copies makes them again."""
    plant = PLANTS["s7"]
    async with simulator(hass, "s7") as sim:
        entry = await plant_entry(hass, "s7", sim, [shutter(plant, 1)], "exp")
        form = await open_copies(hass, entry, "shutter1")
        await step(hass, form, {"count": COPIES, "name": "Shutter {n}", **plant.form})
        text = dump_config(entry)
        assert "template:" in text
        assert text.count("copy_of:") == COPIES

        pasted = load_config(text, entry.version)
        by_title = {s["title"]: dict(s["data"]) for s in pasted.subentries}
        assert by_title == machines(entry)

        original = next(s for s in pasted.subentries if s["title"] == "Shutter 1")
        document = text.split("subentries:")[0] + "subentries:\n"
        bare = load_config(
            document + _subentry_yaml(original["title"], dict(original["data"])), entry.version
        )
        remade = {s["title"]: dict(s["data"]) for s in bare.subentries}
        assert sorted(remade) == sorted(machines(entry))
        for n in range(1, 13):
            assert layout(remade[f"Shutter {n}"]) == layout(shutter(plant, n)["data"])

        record = dict(original["data"][CONF_TEMPLATE]) | {"stride": 2}
        bad = dict(original["data"]) | {CONF_TEMPLATE: record}
        with pytest.raises(ConfigFileError) as refused:
            load_config(document + _subentry_yaml("Shutter 1", bad), entry.version)
        assert refused.value.key == "config_template"
        assert "overlaps" in refused.value.placeholders["problem"]

        unnamed = dict(original["data"]) | {CONF_TEMPLATE: record | {"stride": 24, "name": "X"}}
        with pytest.raises(ConfigFileError) as refused:
            load_config(document + _subentry_yaml("Shutter 1", unnamed), entry.version)
        assert refused.value.placeholders["problem"] == "its names need {n}"


def _subentry_yaml(title: str, data: dict[str, Any]) -> str:
    """Return one machine as the file's subentries list holds it."""
    import yaml

    block = [{"type": SUBENTRY_DEVICE, "title": title, "unique_id": None, "data": data}]
    return yaml.safe_dump(block, sort_keys=False, allow_unicode=True)


async def test_pasted_file_makes_the_copies_it_lacks(hass: HomeAssistant) -> None:
    """A file holding Shutter 1 and its record alone adds the PLC with all twelve shutters."""
    plant = PLANTS["softplc"]
    async with simulator(hass, "softplc") as sim:
        entry = await plant_entry(hass, "softplc", sim, [shutter(plant, 1)], "pst")
        form = await open_copies(hass, entry, "shutter1")
        await step(hass, form, {"count": COPIES, "name": "Shutter {n}", **plant.form})
        made = machines(entry)
        text = await export(hass, entry)
        read = load_config(text, entry.version)
        original = next(s for s in read.subentries if s["title"] == "Shutter 1")
        document = text.split("subentries:")[0] + "subentries:\n"
        bare = document + _subentry_yaml("Shutter 1", dict(original["data"]))
        await hass.config_entries.async_remove(entry.entry_id)

        result = await confirm(hass, await paste(hass, bare), {})
        assert result["type"] is FlowResultType.CREATE_ENTRY, result.get("errors")
        pasted = hass.config_entries.async_get_entry(result["result"].entry_id)
        assert pasted is not None
        remade = {
            s.title: dict(s.data)
            for s in pasted.subentries.values()
            if s.subentry_type == SUBENTRY_DEVICE
        }
        assert sorted(remade) == sorted(made)
        assert {title: layout(data) for title, data in remade.items()} == {
            title: layout(data) for title, data in made.items()
        }
