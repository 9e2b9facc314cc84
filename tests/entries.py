"""Entries as the flows store them: points, machines, a PLC's entry; set up, polled, called.

The S7-200 SMART entry most Home Assistant tests use (POINTS, `make_entry`) is here too; the
simulators of every family, `PlcUnderTest` and the `plc` fixtures are in tests/harness.py.
Registered for every test through `pytest_plugins` in tests/conftest.py.
"""

from __future__ import annotations

from collections.abc import (
    AsyncGenerator,
    AsyncIterator,
    Generator,
    Iterable,
)
from contextlib import asynccontextmanager
from datetime import datetime, timedelta
from typing import Any
from unittest.mock import patch

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import (
    ConfigEntryState,
    ConfigSubentryDataWithId,
)
from homeassistant.const import (
    CONF_HOST,
    CONF_NAME,
    CONF_PASSWORD,
    CONF_PORT,
    CONF_SCAN_INTERVAL,
    CONF_USERNAME,
    Platform,
)
from homeassistant.core import HomeAssistant
from homeassistant.helpers import device_registry as dr
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, async_fire_time_changed

from custom_components import plc_bridge
from custom_components.plc_bridge import PLATFORMS
from custom_components.plc_bridge.const import (
    CONF_ADDRESS,
    CONF_DATA_TYPE,
    CONF_FINGERPRINT,
    CONF_OFFSET,
    CONF_OPTIONS,
    CONF_PLATFORM,
    CONF_POINTS,
    CONF_READ_ONLY,
    CONF_SCALE,
    CONF_TLS,
    CONF_VENDOR,
    DOMAIN,
    SUBENTRY_DEVICE,
    SUBENTRY_POINT,
)
from custom_components.plc_bridge.runtime.polling import EDIT_DELAY
from simulators.s7_smart import DEFAULT_PASSWORD, DEFAULT_USER, S7SmartSimulator
from tests.loopback import Server, running

SCAN_INTERVAL = 10.0
ENTRY_ID = "01JPLCBR1DGE0000000000TEST"
UNIQUE_ID = "plc-bridge-test"
CLOCK = datetime(2026, 3, 1, 12, 30, 0)  # the simulator's clock (naive PLC local time)


DEVICE_ID = "boiler"
"""The subentry id of the device that holds the points of the test entries."""
type PointData = tuple[str, dict[str, Any]]
"""A point as a device subentry stores it: its id and its data."""


def point(
    point_id: str, title: str, platform: str, address: str, data_type: str, **extra: Any
) -> PointData:
    """Return a point as the device subentry flow stores it."""
    data = {
        CONF_NAME: title,
        CONF_PLATFORM: platform,
        CONF_ADDRESS: address,
        CONF_DATA_TYPE: data_type,
        CONF_SCALE: 1.0,
        CONF_OFFSET: 0.0,
        CONF_READ_ONLY: False,
    }
    return point_id, data | extra


def device(
    points: Iterable[PointData], subentry_id: str = DEVICE_ID, title: str = "Boiler"
) -> ConfigSubentryDataWithId:
    """Return a device subentry holding the points."""
    return ConfigSubentryDataWithId(
        data={CONF_POINTS: dict(points)},
        subentry_id=subentry_id,
        subentry_type=SUBENTRY_DEVICE,
        title=title,
        unique_id=None,
    )


def legacy_point(point_data: PointData) -> ConfigSubentryDataWithId:
    """Return a point as a version 1 entry stored it: one subentry of its own."""
    point_id, data = point_data
    data = dict(data)
    title = data.pop(CONF_NAME)
    return ConfigSubentryDataWithId(
        data=data,
        subentry_id=point_id,
        subentry_type=SUBENTRY_POINT,
        title=title,
        unique_id=f"{data[CONF_ADDRESS]}|{data[CONF_DATA_TYPE]}",
    )


POINTS = [
    point(
        "temperature",
        "Temperature",
        "sensor",
        "VD100",
        "float",
        unit_of_measurement="°C",
        device_class="temperature",
        state_class="measurement",
    ),
    point("pressure", "Pressure", "sensor", "VW10", "signed", scale=0.1, unit_of_measurement="bar"),
    point("label", "Label", "sensor", "VB200", "string"),
    point("raw", "Raw", "sensor", "VD300", "raw"),
    point("door", "Door", "binary_sensor", "I0.0", "signed", device_class="door"),
    point("pump", "Pump", "switch", "Q0.0", "signed"),
    point(
        "setpoint",
        "Setpoint",
        "number",
        "VW20",
        "signed",
        scale=0.5,
        offset=10.0,
        min=10.0,
        max=60.0,
        step=0.5,
    ),
    point("clock", "Clock", "datetime", "DATE", "signed"),
]
"""A point of every platform and of every S7-200 SMART data mode."""


def entry_data(
    vendor: str,
    sim: Server,
    credentials: tuple[str, str] | None,
    tls: str = "none",
    options: dict[str, Any] | None = None,
) -> dict[str, Any]:
    """Return the entry data the config flow stores for a simulator (its pin, if it has one).

    `credentials` (user, password) are stored for a vendor that asks for them, None for one that
    does not.
    """
    data: dict[str, Any] = {CONF_VENDOR: vendor, CONF_HOST: sim.host, CONF_PORT: sim.port}
    if credentials is not None:
        data[CONF_USERNAME], data[CONF_PASSWORD] = credentials
    fingerprint = getattr(sim, "fingerprint", None) or ""
    return data | {CONF_TLS: tls, CONF_FINGERPRINT: fingerprint, CONF_OPTIONS: options or {}}


def sim_data(sim: S7SmartSimulator, **changes: Any) -> dict[str, Any]:
    """Return entry data for the simulator: pinned certificate, default user."""
    return entry_data("s7_smart", sim, (DEFAULT_USER, DEFAULT_PASSWORD), "pin") | changes


def add_entry(
    hass: HomeAssistant,
    *,
    title: str,
    entry_id: str,
    unique_id: str,
    data: dict[str, Any],
    points: Iterable[PointData] = (),
    subentries: list[ConfigSubentryDataWithId] | None = None,
    version: int = 2,
    minor_version: int = 2,
) -> MockConfigEntry:
    """Add a PLC's entry, polled every SCAN_INTERVAL (not set up).

    Its points go into one device with the PLC's name, as a migrated entry's: entity ids stay
    the PLC's. `subentries` (and `version`, `minor_version`) store other shapes instead.
    """
    points = list(points)
    if subentries is None:
        subentries = [device(points, title=title)] if points else []
    entry = MockConfigEntry(
        domain=DOMAIN,
        title=title,
        entry_id=entry_id,
        unique_id=unique_id,
        data=data,
        options={CONF_SCAN_INTERVAL: SCAN_INTERVAL},
        subentries_data=subentries,
        version=version,
        minor_version=minor_version,
    )
    entry.add_to_hass(hass)
    return entry


def make_entry(
    hass: HomeAssistant,
    sim: S7SmartSimulator,
    points: Iterable[PointData] = POINTS,
    **changes: Any,
) -> MockConfigEntry:
    """Add an entry of the simulator with the given points (not set up yet)."""
    return add_entry(
        hass,
        title="S7-200 SMART",
        entry_id=ENTRY_ID,
        unique_id=UNIQUE_ID,
        data=sim_data(sim, **changes),
        points=points,
    )


async def call(
    hass: HomeAssistant, service: str, entry: MockConfigEntry, **data: Any
) -> dict[str, Any] | None:
    """Call an action of the integration for an entry and return its response."""
    return await hass.services.async_call(
        DOMAIN,
        service,
        {"config_entry_id": entry.entry_id, **data},
        blocking=True,
        return_response=service == "read",
    )


async def poll(hass: HomeAssistant, freezer: FrozenDateTimeFactory, times: int = 1) -> None:
    """Let the poll interval pass (`times` times) and wait for the polls."""
    for _ in range(times):
        freezer.tick(timedelta(seconds=SCAN_INTERVAL))
        async_fire_time_changed(hass)
        await hass.async_block_till_done(wait_background_tasks=True)


async def read_edits(hass: HomeAssistant, freezer: FrozenDateTimeFactory) -> None:
    """Let the edits pause long enough for the points they added to be read, and wait for it."""
    freezer.tick(timedelta(seconds=EDIT_DELAY))
    async_fire_time_changed(hass)
    await hass.async_block_till_done(wait_background_tasks=True)


async def unload_all(hass: HomeAssistant) -> None:
    """Unload every loaded PLC Bridge entry (its client logs out)."""
    for entry in hass.config_entries.async_entries(DOMAIN):
        if entry.state is ConfigEntryState.LOADED:
            assert await hass.config_entries.async_unload(entry.entry_id)


@asynccontextmanager
async def serving[S: Server](hass: HomeAssistant, sim: S) -> AsyncIterator[S]:
    """Start a simulator; afterwards unload every entry (their clients log out), then stop it."""
    async with running(sim):
        try:
            yield sim
        finally:
            await unload_all(hass)


async def set_up(hass: HomeAssistant, entry: MockConfigEntry) -> MockConfigEntry:
    """Set an entry up and wait until it is; return it."""
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    return entry


@pytest.fixture
def s7_smart_entry(hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator) -> MockConfigEntry:
    """The simulator's entry: pinned certificate, a point of every platform."""
    return make_entry(hass, s7_smart_ha_sim)


@pytest.fixture
def platforms() -> list[Platform]:
    """The platforms to set up (a test module narrows this for its snapshot)."""
    return PLATFORMS


@pytest.fixture
async def setup_integration(
    hass: HomeAssistant, s7_smart_entry: MockConfigEntry, platforms: list[Platform]
) -> AsyncGenerator[MockConfigEntry]:
    """Set the simulator's entry up with the chosen platforms (kept for its unload)."""
    with patch("custom_components.plc_bridge.PLATFORMS", platforms):
        assert await hass.config_entries.async_setup(s7_smart_entry.entry_id)
        await hass.async_block_till_done()
        yield s7_smart_entry
        await unload_all(hass)


@pytest.fixture
def entity_registry_enabled_by_default() -> Generator[None]:
    """Create the entities that are disabled by default as enabled."""
    with patch("homeassistant.helpers.entity.Entity.entity_registry_enabled_default", True):
        yield


def plc_device(registry: dr.DeviceRegistry, identifier: str) -> dr.DeviceEntry | None:
    """Return the device of the test entry registered under an identifier, if any.

    Through the entry's devices: the registry's look-up by identifier is deprecated on the
    current release and missing on the oldest.
    """
    devices = dr.async_entries_for_config_entry(registry, ENTRY_ID)
    return next((dev for dev in devices if (DOMAIN, identifier) in dev.identifiers), None)


def set_points(
    hass: HomeAssistant,
    entry: MockConfigEntry,
    points: dict[str, Any],
    subentry_id: str = DEVICE_ID,
) -> None:
    """Store a device subentry's points as its flow would (the entry follows in place)."""
    subentry = entry.subentries[subentry_id]
    hass.config_entries.async_update_subentry(
        entry, subentry, data={**subentry.data, CONF_POINTS: points}
    )


def edit_point(hass: HomeAssistant, entry: MockConfigEntry, point_id: str, **changes: Any) -> None:
    """Change fields of one point of the test device."""
    points = dict(entry.subentries[DEVICE_ID].data[CONF_POINTS])
    points[point_id] = {**points[point_id], **changes}
    set_points(hass, entry, points)


def remove_point(hass: HomeAssistant, entry: MockConfigEntry, point_id: str) -> None:
    """Remove one point of the test device."""
    points = dict(entry.subentries[DEVICE_ID].data[CONF_POINTS])
    del points[point_id]
    set_points(hass, entry, points)


def word(index: int) -> str:
    """Return the address of the index-th word of the V area."""
    return f"VW{2 * index}"


def plant_entry(
    hass: HomeAssistant, sim: S7SmartSimulator, machines: int, per_machine: int
) -> MockConfigEntry:
    """Add a PLC whose word sensors are spread over machines (device subentries), not set up."""
    subentries = [
        device(
            [
                point(
                    f"d{d}p{i}", f"Word {i}", "sensor", f"VW{2 * (per_machine * d + i)}", "signed"
                )
                for i in range(per_machine)
            ],
            subentry_id=f"device{d}",
            title=f"Machine {d}",
        )
        for d in range(machines)
    ]
    return add_entry(
        hass,
        title="S7-200 SMART",
        entry_id=ENTRY_ID,
        unique_id=UNIQUE_ID,
        data=sim_data(sim),
        subentries=subentries,
    )


@pytest.fixture
def setups(hass: HomeAssistant, monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """Record each setup of an entry from now on (its id), through the real setup."""
    done: list[str] = []
    original = plc_bridge.async_setup_entry

    async def counted(hass: HomeAssistant, entry: Any) -> bool:
        done.append(entry.entry_id)
        return await original(hass, entry)

    monkeypatch.setattr(plc_bridge, "async_setup_entry", counted)
    return done
