"""Exposes on every vendor: where each simulator takes a REAL, a BOOL and a burst of integers.

`VENDORS` names, per vendor, the simulator fixture, how to make its entry, the addresses the
tests write and how to read them back at the simulator, and how the simulator counts writes.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from datetime import timedelta
import struct
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import ConfigSubentry
from homeassistant.const import CONF_ATTRIBUTE, CONF_ENTITY_ID
from homeassistant.core import HomeAssistant
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
    SUBENTRY_EXPOSE,
)
from custom_components.plc_bridge.runtime.expose import BATCH_WINDOW
from tests.ha_fixtures import PointData, make_entry, point, set_up
from tests.plcnext_ha_fixtures import make_plcnext_entry
from tests.s7_ha_fixtures import make_s7_entry
from tests.softplc_ha_fixtures import make_softplc_entry, pem_pair
from tests.tecomat_ha_fixtures import make_tecomat_entry

type Target = tuple[str, str]
"""An address and its data type."""
PLCNEXT = "Arp.Plc.Eclr/MainInstance."


def _softplc_read(sim: Any, address: str, _data_type: str) -> Any:
    """Return what a SoftPLC simulator holds at `N7:3`, `F8:1` or `B3:0/5`."""
    file, _, rest = address.partition(":")
    element, _, bit = rest.partition("/")
    word = sim.files[file[0], int(file[1:])].words[int(element)]
    return bool(word >> int(bit) & 1) if bit else word


def _s7_read(sim: Any, address: str, data_type: str) -> Any:
    """Return what an S7 simulator holds at `DB1.DBW100`, `DB1.DBD200` or `M10.0`."""
    if address.startswith("M"):
        byte, _, bit = address[1:].partition(".")
        return bool(sim.get_bytes("M", int(byte), 1)[0] >> int(bit) & 1)
    start = int(address.split(".DB")[1][1:])
    if data_type == "REAL":
        return struct.unpack(">f", sim.get_db(1, start, 4))[0]
    return int.from_bytes(sim.get_db(1, start, 2), "big", signed=True)


def _s7_smart_entry(hass: HomeAssistant, sim: Any, points: list[PointData]) -> MockConfigEntry:
    """Return the S7-200 SMART entry."""
    return make_entry(hass, sim, points)


def _softplc_entry(hass: HomeAssistant, sim: Any, points: list[PointData]) -> MockConfigEntry:
    """Return the SoftPLC entry, with the client certificate its PUTs need."""
    return make_softplc_entry(hass, sim, points, **{CONF_OPTIONS: pem_pair(sim)})


@dataclass(frozen=True, slots=True)
class VendorCase:
    """One vendor's simulator, entry, targets, read-back and write count."""

    vendor: str
    sim: str  # the simulator's fixture
    entry: Callable[[HomeAssistant, Any, list[PointData]], MockConfigEntry]
    real: Target
    bool: Target
    burst: list[Target]
    read: Callable[[Any, str, str], Any]
    write_call: str | None  # the simulator's count of write requests (None: all requests)

    def writes(self, sim: Any) -> int:
        """Return the write requests the simulator has served (SoftPLC: every request)."""
        return sim.requests if self.write_call is None else sim.calls.get(self.write_call, 0)


VENDORS = [
    VendorCase(
        "s7_smart",
        "s7_smart_sim",
        _s7_smart_entry,
        ("VD400", "float"),
        ("M10.0", "signed"),
        [(f"VW{500 + 2 * i}", "signed") for i in range(10)],
        lambda sim, address, data_type: sim.get(address, data_type),
        "write",
    ),
    VendorCase(
        "tecomat",
        "tecomat_sim",
        make_tecomat_entry,
        ("plcData.varReal", "REAL"),
        ("plcData.varBool0", "BOOL"),
        [(f"arr2[{i // 4}][{i % 4}]", "REAL") for i in range(10)],
        lambda sim, address, _data_type: sim.get(address),
        "PutObject",
    ),
    VendorCase(
        "plcnext",
        "plcnext_sim",
        make_plcnext_entry,
        (PLCNEXT + "Setpoint", "REAL"),
        (PLCNEXT + "Pump", "BOOL"),
        [(f"{PLCNEXT}Levels[{i}]", "INT") for i in range(1, 5)]
        + [
            (PLCNEXT + name, kind)
            for name, kind in (
                ("Speed", "INT"),
                ("Small", "SINT"),
                ("Tiny", "USINT"),
                ("Wide", "UINT"),
                ("Energy", "UDINT"),
                ("Total", "LINT"),
            )
        ],
        lambda sim, address, _data_type: sim.get(address),
        "PUT variables",
    ),
    VendorCase(
        "softplc",
        "softplc_sim",
        _softplc_entry,
        ("F8:1", "REAL"),
        ("B3:0/5", "BOOL"),
        [(f"N7:{i}", "INT") for i in range(10)],
        _softplc_read,
        None,
    ),
    VendorCase(
        "s7",
        "s7_ha_sim",
        make_s7_entry,
        ("DB1.DBD200", "REAL"),
        ("M10.0", "BOOL"),
        [(f"DB1.DBW{100 + 2 * i}", "INT") for i in range(10)],
        _s7_read,
        "write",
    ),
]


def shown(case: VendorCase) -> PointData:
    """Return a sensor point polling the vendor's REAL target (it shows what exposes write)."""
    return point("shown", "Shown", "sensor", case.real[0], case.real[1])


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
    hass: HomeAssistant, freezer: FrozenDateTimeFactory, vendor: VendorCase, sim: Any
) -> tuple[MockConfigEntry, Burst]:
    """Expose one entity to each burst address, set up, change them all at once; count."""
    entities = [f"input_number.level_{index}" for index in range(len(vendor.burst))]
    for entity_id in entities:
        hass.states.async_set(entity_id, "0")
    entry = vendor.entry(hass, sim, [shown(vendor)])
    for entity_id, target in zip(entities, vendor.burst, strict=True):
        add_expose(hass, entry, entity_id, target)
    await set_up(hass, entry)
    client = entry.runtime_data.client
    writes, requests = vendor.writes(sim), client.metrics.requests
    sent = [index % 100 + 11 for index in range(len(entities))]
    for entity_id, value in zip(entities, sent, strict=True):
        hass.states.async_set(entity_id, str(value))
    await settle(hass, freezer)
    return entry, Burst(
        writes=vendor.writes(sim) - writes,
        requests=client.metrics.requests - requests,
        sent=sent,
        held=[vendor.read(sim, *target) for target in vendor.burst],
    )
