"""The one write guard: read-only data by what it covers, inputs never; who may read and set."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

from homeassistant.auth.const import GROUP_ID_USER
from homeassistant.components.datetime import (
    ATTR_DATETIME,
    DOMAIN as DATETIME_DOMAIN,
    SERVICE_SET_VALUE as SET_DATETIME,
)
from homeassistant.components.number import (
    ATTR_VALUE,
    DOMAIN as NUMBER_DOMAIN,
    SERVICE_SET_VALUE as SET_NUMBER,
)
from homeassistant.const import ATTR_ENTITY_ID
from homeassistant.core import Context, HomeAssistant
from homeassistant.exceptions import ServiceValidationError, Unauthorized
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, MockUser
import voluptuous as vol

from custom_components.plc_bridge.const import DOMAIN
from custom_components.plc_bridge.plc import Point
from custom_components.plc_bridge.plc.vendors import client_class
from custom_components.plc_bridge.runtime.write_guard import WriteGuard
from custom_components.plc_bridge.services import MAX_READ
from simulators.s7_smart import S7SmartSimulator
from tests.entries import POINTS, call, make_entry, point

pytestmark = pytest.mark.no_pacing

LOCKED = point("locked", "Locked", "sensor", "VW50", "signed", read_only=True)
NEIGHBOUR = point("neighbour", "Neighbour", "number", "VB51", "unsigned")
"""A writable number over the second byte of the read-only word."""


@pytest.fixture
async def locked_entry(hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator) -> MockConfigEntry:
    """The simulator's entry with a read-only word and a number on one of its bytes."""
    entry = make_entry(hass, s7_smart_ha_sim, [*POINTS, LOCKED, NEIGHBOUR])
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    return entry


@pytest.mark.usefixtures("locked_entry")
@pytest.mark.parametrize(
    ("address", "data_type", "message"),
    [
        ("VW50", "unsigned", "VW50 is a read-only point; nothing was sent"),
        ("VB50", "unsigned", "VB50 covers data of the read-only point VW50; nothing was sent"),
        ("vb51", "raw", "VB51 covers data of the read-only point VW50; nothing was sent"),
        ("VD48", "signed", "VD48 covers data of the read-only point VW50; nothing was sent"),
        ("V50.3", "signed", "V50.3 covers data of the read-only point VW50; nothing was sent"),
        ("vw50", "signed", "VW50 is a read-only point; nothing was sent"),
        ("I0.1", "signed", "I0.1 can never be written (an input or a read-only area of the PLC)"),
        ("AIW16", "signed", "AIW16 can never be written (an input or a read-only area of the PLC)"),
        ("SMB10", "unsigned", "SMB10 can never be written (an input or a read-only area of the"),
    ],
)
async def test_write_action_refuses_read_only_data(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    address: str,
    data_type: str,
    message: str,
) -> None:
    """Another width, mode or spelling of read-only data, or an input: refused, nothing sent."""
    before = s7_smart_ha_sim.calls["write"]
    value: Any = [1] if data_type == "raw" else 1
    with pytest.raises(ServiceValidationError) as err:
        await call(
            hass,
            "write",
            hass.config_entries.async_entries(DOMAIN)[0],
            points=[
                {"address": "VW30", "data_type": "signed", "value": 7},
                {"address": address, "data_type": data_type, "value": value},
            ],
        )
    assert str(err.value).startswith(message)
    assert s7_smart_ha_sim.calls["write"] == before
    assert s7_smart_ha_sim.get("VW30") == 0


async def test_write_next_to_read_only_data_goes_through(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, locked_entry: MockConfigEntry
) -> None:
    """The bytes beside a read-only word stay writable."""
    await call(
        hass,
        "write",
        locked_entry,
        points=[{"address": "VB52", "data_type": "unsigned", "value": 9}],
    )
    assert s7_smart_ha_sim.get("VB52", "unsigned") == 9


async def test_entity_write_passes_the_same_guard(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, locked_entry: MockConfigEntry
) -> None:
    """A number over a read-only word's byte cannot write it either."""
    before = s7_smart_ha_sim.calls["write"]
    with pytest.raises(ServiceValidationError, match="VB51 covers data of the read-only point"):
        await hass.services.async_call(
            NUMBER_DOMAIN,
            SET_NUMBER,
            {ATTR_ENTITY_ID: "number.s7_200_smart_neighbour", ATTR_VALUE: 3},
            blocking=True,
        )
    assert s7_smart_ha_sim.calls["write"] == before


def test_names_folded_and_elements_covered() -> None:
    """TecoApi and PLCnext: another case, or an element or member of read-only data."""
    for vendor in ("tecomat", "plcnext"):
        client = client_class(vendor)
        guard = WriteGuard(client, [client.validate_point(Point("Main.Recipe", "INT"))])
        for address in ("main.recipe", "MAIN.Recipe[2]", "Main.Recipe.Weight"):
            with pytest.raises(ServiceValidationError):
                guard.check(client.validate_point(Point(address, "INT")))
        guard.check(client.validate_point(Point("Main.RecipeName", "INT")))


async def test_read_list_is_capped(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, locked_entry: MockConfigEntry
) -> None:
    """A read names at most MAX_READ points: a longer list never reaches the PLC."""
    before = s7_smart_ha_sim.calls["read"]
    points = [{"address": f"VW{2 * index}", "data_type": "signed"} for index in range(MAX_READ)]
    with pytest.raises(vol.Invalid):
        await call(
            hass,
            "read",
            locked_entry,
            points=[*points, {"address": "VW999", "data_type": "signed"}],
        )
    assert s7_smart_ha_sim.calls["read"] == before
    response = await call(hass, "read", locked_entry, points=points)
    assert response is not None
    assert len(response["values"]) == MAX_READ


@pytest.mark.usefixtures("entity_registry_enabled_by_default")
async def test_clock_entity_for_administrators_only(
    hass: HomeAssistant,
    s7_smart_ha_sim: S7SmartSimulator,
    locked_entry: MockConfigEntry,
    hass_admin_user: MockUser,
) -> None:
    """A user who may control entities but is no administrator cannot set the PLC clock."""
    group = await hass.auth.async_get_group(GROUP_ID_USER)
    user = MockUser(groups=[group]).add_to_hass(hass)
    data = {
        ATTR_ENTITY_ID: "datetime.s7_200_smart_plc_clock",
        ATTR_DATETIME: datetime(2026, 7, 4, 18, 0, tzinfo=UTC),
    }
    before = s7_smart_ha_sim.clock
    with pytest.raises(Unauthorized):
        await hass.services.async_call(
            DATETIME_DOMAIN, SET_DATETIME, data, blocking=True, context=Context(user_id=user.id)
        )
    assert s7_smart_ha_sim.clock == before
    await hass.services.async_call(
        DATETIME_DOMAIN,
        SET_DATETIME,
        data,
        blocking=True,
        context=Context(user_id=hass_admin_user.id),
    )
    assert s7_smart_ha_sim.clock == datetime(2026, 7, 4, 11, 0)
