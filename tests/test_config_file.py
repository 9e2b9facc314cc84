"""The whole PLC as a file: exported by the action, removed, added again from the pasted text.

On every vendor's simulator the PLC comes back with the same entities (unique ids, entity ids,
states), the same machines, points and options; the secrets are never in the text.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import SOURCE_USER, ConfigEntry
from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_PORT
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import (
    CONF_SEND_ON_START,
    DOMAIN,
    SUBENTRY_EXPOSE,
)
from custom_components.plc_bridge.flows.base import device_unique_id
from custom_components.plc_bridge.flows.config_file_flow import CONF_CONFIGURATION, PASTE
from custom_components.plc_bridge.model.expose import CONF_SEND
from custom_components.plc_bridge.model.poll_classes import (
    CONF_FAST_INTERVAL,
    CONF_POLL,
    CONF_SLOW_INTERVAL,
)
from custom_components.plc_bridge.runtime.connection import create_client
from simulators.plcnext import DEFAULT_PASSWORD as PLCNEXT_PASSWORD
from simulators.s7_smart import DEFAULT_PASSWORD as SMART_PASSWORD
from simulators.tecomat import DEFAULT_PASSWORD as TECOMAT_PASSWORD
from tests.entries import POINTS, PointData, add_entry, device, sim_data
from tests.flows.forms import suggested, translated
from tests.harness import (
    PLCNEXT_POINTS,
    S7_POINTS,
    S7_TITLE,
    SOFTPLC_POINTS,
    TECOMAT_POINTS,
    add_expose,
    fill,
    pem_pair,
    plcnext_data,
    s7_data,
    settle,
    softplc_data,
    tecomat_data,
)
from tests.test_cover import SHUTTER as SMART_COVER
from tests.test_plcnext_composite import POINTS as PLCNEXT_FAN
from tests.test_s7_composite import POINTS as S7_GATE
from tests.test_softplc_composite import POINTS as SOFTPLC_LIGHT
from tests.test_tecomat_composite import POINTS as TECOMAT_ROOM

pytestmark = pytest.mark.no_pacing

CONFIG = ("config",)


@dataclass(frozen=True, slots=True)
class Vendor:
    """How a vendor's PLC is made in the tests: its simulator, entry data, points and secrets."""

    sim: str  # the fixture of its started simulator
    title: str
    data: Callable[[Any, dict[str, str]], dict[str, Any]]  # of the simulator, with the secrets
    points: list[PointData]
    parts: list[PointData]  # an entity of several points, in a machine of its own
    secrets: Callable[[Any], dict[str, str]]  # what the secrets page takes, by field


VENDORS = {
    "s7_smart": Vendor(
        "s7_smart_ha_sim",
        "S7-200 SMART",
        lambda sim, _: sim_data(sim),
        POINTS,
        SMART_COVER,
        lambda _: {CONF_PASSWORD: SMART_PASSWORD},
    ),
    "tecomat": Vendor(
        "tecomat_ha_sim",
        "Fx2 CP2080",
        lambda sim, _: tecomat_data(sim),
        TECOMAT_POINTS,
        TECOMAT_ROOM,
        lambda _: {CONF_PASSWORD: TECOMAT_PASSWORD},
    ),
    "plcnext": Vendor(
        "plcnext_ha_sim",
        "PLCnext",
        lambda sim, _: plcnext_data(sim),
        PLCNEXT_POINTS,
        PLCNEXT_FAN,
        lambda _: {CONF_PASSWORD: PLCNEXT_PASSWORD},
    ),
    "softplc": Vendor(
        "softplc_ha_sim",
        "SoftPLC",
        lambda sim, secrets: softplc_data(sim, vendor_options=secrets),
        SOFTPLC_POINTS,
        SOFTPLC_LIGHT,
        pem_pair,
    ),
    "s7": Vendor(
        "s7_ha_sim",
        S7_TITLE,
        lambda sim, _: s7_data(sim, family="s7_300_1500"),  # as the flow stores it
        S7_POINTS,
        S7_GATE,
        lambda _: {},
    ),
}


async def flow_unique_id(hass: HomeAssistant, data: dict[str, Any]) -> str:
    """Return the unique id the config flow gives the PLC at this address (it connects)."""
    client = create_client(hass, data)
    try:
        return device_unique_id(await client.connect(), data)
    finally:
        await client.close()


async def original(
    hass: HomeAssistant, vendor: Vendor, sim: Any, secrets: dict[str, str]
) -> MockConfigEntry:
    """Add and set up the vendor's PLC as the config flow would have: two machines."""
    data = vendor.data(sim, secrets)
    entry = add_entry(
        hass,
        title=vendor.title,
        entry_id="01JPLCBR1DGE000000ORIGINAL",
        unique_id=await flow_unique_id(hass, data),
        data=data,
        subentries=[
            device(vendor.points, subentry_id="plain", title=vendor.title),
            device(vendor.parts, subentry_id="parts", title="Machine"),
        ],
    )
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    return entry


def entities(hass: HomeAssistant, entry: ConfigEntry) -> dict[str, str]:
    """Return the entry's entity ids by unique id."""
    registered = er.async_entries_for_config_entry(er.async_get(hass), entry.entry_id)
    return {registry_entry.unique_id: registry_entry.entity_id for registry_entry in registered}


def states(hass: HomeAssistant, entity_ids: list[str]) -> dict[str, Any]:
    """Return each entity's state and attributes."""
    shown = {entity_id: hass.states.get(entity_id) for entity_id in entity_ids}
    return {eid: (s.state, dict(s.attributes)) if s else None for eid, s in shown.items()}


def contents(entry: ConfigEntry) -> tuple[Any, ...]:
    """Return what the file carries of an entry: title, data, options, subentries."""
    subentries = sorted(
        (s.subentry_type, s.title, s.unique_id, dict(s.data)) for s in entry.subentries.values()
    )
    return entry.title, dict(entry.data), dict(entry.options), subentries


async def export(hass: HomeAssistant, entry: ConfigEntry) -> str:
    """Return the text the export_config action gives for the entry."""
    response = await hass.services.async_call(
        DOMAIN,
        "export_config",
        {"config_entry_id": entry.entry_id},
        blocking=True,
        return_response=True,
    )
    assert response is not None
    text = response["yaml"]
    assert isinstance(text, str)
    return text


async def paste(hass: HomeAssistant, text: str) -> Any:
    """Start adding a PLC, choose to paste a configuration, and paste the text."""
    result = await hass.config_entries.flow.async_init(DOMAIN, context={"source": SOURCE_USER})
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {"next_step_id": PASTE}
    )
    assert result["step_id"] == PASTE
    translated(result, *CONFIG)
    return translated(
        await hass.config_entries.flow.async_configure(
            result["flow_id"], {CONF_CONFIGURATION: text}
        ),
        *CONFIG,
    )


async def confirm(hass: HomeAssistant, result: Any, secrets: dict[str, str]) -> Any:
    """Take the pages after the paste as the file filled them in, adding the secrets.

    The connection page (and a second one), the certificate page where TLS is pinned, the list
    of exposes: each is submitted as suggested, until the entry is made or a page shows errors.
    """
    while result["type"] is FlowResultType.FORM and not result.get("errors"):
        values: dict[str, Any] = {}
        for marker in result["data_schema"].schema if result["data_schema"] else {}:
            field = str(marker)
            if field in secrets:
                values[field] = secrets[field]
            elif (value := suggested(result, field)) is not None:
                values[field] = value
        result = translated(
            await hass.config_entries.flow.async_configure(result["flow_id"], values), *CONFIG
        )
    return result


@pytest.fixture
def vendor_sim(request: pytest.FixtureRequest) -> tuple[Vendor, Any]:
    """The vendor the test is parametrized with, and its started simulator holding values."""
    vendor = VENDORS[request.param]
    sim = request.getfixturevalue(vendor.sim)
    if request.param == "s7":
        fill(sim)
    return vendor, sim


@pytest.mark.parametrize("vendor_sim", VENDORS, indirect=True)
async def test_round_trip(hass: HomeAssistant, vendor_sim: tuple[Vendor, Any]) -> None:
    """Export, remove, paste: the same PLC with the same entities, machines and options."""
    vendor, sim = vendor_sim
    secrets = vendor.secrets(sim)
    entry = await original(hass, vendor, sim, secrets)
    before = entities(hass, entry)
    shown = states(hass, list(before.values()))
    kept = contents(entry)
    assert len(before) > len(vendor.points)
    text = await export(hass, entry)
    for secret in secrets.values():
        assert secret.strip() not in text
    assert await hass.config_entries.async_remove(entry.entry_id)
    await hass.async_block_till_done()
    result = await paste(hass, text)
    assert result["step_id"].startswith("connection")  # the host and port, shown first
    assert suggested(result, CONF_HOST) == entry.data[CONF_HOST]
    assert suggested(result, CONF_PORT) == entry.data[CONF_PORT]
    result = await confirm(hass, result, secrets)
    assert result["type"] is FlowResultType.CREATE_ENTRY
    await hass.async_block_till_done()
    new = result["result"]
    assert contents(new) == kept
    assert new.unique_id == entry.unique_id
    after = entities(hass, new)
    if new.unique_id.endswith(f":{sim.port}"):
        # Neither a serial nor a MAC: the entities are keyed by the entry id, which is new.
        before = {uid.replace(entry.entry_id, new.entry_id): eid for uid, eid in before.items()}
    assert after == before
    assert states(hass, list(after.values())) == shown


async def test_round_trip_carries_exposes_and_poll_classes(
    hass: HomeAssistant, s7_smart_ha_sim: Any, freezer: FrozenDateTimeFactory
) -> None:
    """An expose, points of each poll class and the classes' intervals come back as they were."""
    vendor = VENDORS["s7_smart"]
    hass.states.async_set("sensor.outdoor", "21.5")
    classes = {0: "fast", 1: "slow"}
    classed = [
        (point_id, {**data, CONF_POLL: classes[index]} if index in classes else data)
        for index, (point_id, data) in enumerate(vendor.points)
    ]
    entry = add_entry(
        hass,
        title=vendor.title,
        entry_id="01JPLCBR1DGE000000ORIGINAL",
        unique_id=await flow_unique_id(hass, sim_data(s7_smart_ha_sim)),
        data=sim_data(s7_smart_ha_sim),
        subentries=[device(classed, subentry_id="plain", title=vendor.title)],
    )
    hass.config_entries.async_update_entry(
        entry, options={**entry.options, CONF_FAST_INTERVAL: 2.0, CONF_SLOW_INTERVAL: 120.0}
    )
    add_expose(hass, entry, "sensor.outdoor", ("VD200", "float"), **{CONF_SEND_ON_START: True})
    assert await hass.config_entries.async_setup(entry.entry_id)
    await settle(hass, freezer)
    assert s7_smart_ha_sim.get("VD200", "float") == pytest.approx(21.5)
    kept = contents(entry)
    text = await export(hass, entry)
    assert "sensor.outdoor" in text
    assert await hass.config_entries.async_remove(entry.entry_id)
    await hass.async_block_till_done()
    s7_smart_ha_sim.set("VD200", 0.0, "float")
    result = await paste(hass, text)
    result = await confirm(hass, result, vendor.secrets(s7_smart_ha_sim))
    assert result["type"] is FlowResultType.CREATE_ENTRY
    await settle(hass, freezer)
    new = result["result"]
    (expose,) = [s for s in new.subentries.values() if s.subentry_type == SUBENTRY_EXPOSE]
    assert expose.data[CONF_SEND] is False  # pasted: sends nothing until turned on
    assert contents(new)[:3] == kept[:3]
    assert s7_smart_ha_sim.get("VD200", "float") == 0.0
    sending = {key: value for key, value in expose.data.items() if key != CONF_SEND}
    hass.config_entries.async_update_subentry(new, expose, data=sending)
    await settle(hass, freezer)
    assert contents(new) == kept
    assert s7_smart_ha_sim.get("VD200", "float") == pytest.approx(21.5)  # turned on: it runs
