"""Who may call which action, on which points, and the on-demand read apart from the poll."""

from __future__ import annotations

from homeassistant.core import Context, HomeAssistant
from homeassistant.exceptions import ServiceValidationError, Unauthorized
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, MockUser

from custom_components.plc_bridge.const import DOMAIN
from custom_components.plc_bridge.model.point_table import parse_points, point_order
from custom_components.plc_bridge.plc.vendors.s7_smart import S7SmartClient
from simulators.s7_smart import S7SmartSimulator
from tests.entries import POINTS, call, make_entry, point

pytestmark = pytest.mark.no_pacing


@pytest.mark.parametrize(
    "service", ["write", "sync_clock", "read", "export_points", "export_config"]
)
async def test_actions_for_administrators_only(
    hass: HomeAssistant,
    setup_integration: MockConfigEntry,
    hass_read_only_user: MockUser,
    service: str,
) -> None:
    """A user without administrator rights cannot write, set the clock, read by address or export.

    The configuration export lists every address and the PLC's host, user and certificate pin.

    Reading by address reaches any memory, not only the points shown, and holds the PLC's lock.
    """
    data: dict[str, object] = {"config_entry_id": setup_integration.entry_id}
    if service == "write":
        data["points"] = [{"address": "VW30", "data_type": "signed", "value": 1}]
    if service == "read":
        data["points"] = [{"address": "VD100", "data_type": "float"}]
    with pytest.raises(Unauthorized):
        await hass.services.async_call(
            DOMAIN,
            service,
            data,
            blocking=True,
            context=Context(user_id=hass_read_only_user.id),
            return_response=service in ("read", "export_points", "export_config"),
        )


async def test_read_for_administrators(
    hass: HomeAssistant, setup_integration: MockConfigEntry, hass_admin_user: MockUser
) -> None:
    """An administrator reads any address."""
    response = await hass.services.async_call(
        DOMAIN,
        "read",
        {
            "config_entry_id": setup_integration.entry_id,
            "points": [{"address": "VD100", "data_type": "float"}],
        },
        blocking=True,
        return_response=True,
        context=Context(user_id=hass_admin_user.id),
    )
    assert response == {"values": {"VD100": 21.5}, "errors": {}}


async def test_write_to_a_read_only_point_refused(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """The write action refuses an address a read-only point names; nothing is sent."""
    points = [*POINTS, point("locked", "Locked", "sensor", "VW50", "signed", read_only=True)]
    entry = make_entry(hass, s7_smart_ha_sim, points)
    assert await hass.config_entries.async_setup(entry.entry_id)
    before = s7_smart_ha_sim.calls["write"]
    with pytest.raises(ServiceValidationError, match="VW50 is a read-only point"):
        await call(
            hass, "write", entry, points=[{"address": "vw50", "data_type": "signed", "value": 3}]
        )
    assert s7_smart_ha_sim.calls["write"] == before


async def test_read_action_leaves_the_poll_alone(
    hass: HomeAssistant, setup_integration: MockConfigEntry
) -> None:
    """An on-demand read keeps the poll's counters and plan."""
    client = setup_integration.runtime_data.client
    assert isinstance(client, S7SmartClient)
    metrics = client.metrics.as_dict()
    plan = client._plan
    await call(
        hass, "read", setup_integration, points=[{"address": "VW400", "data_type": "signed"}]
    )
    after = client.metrics.as_dict()
    assert (after["polls"], after["last_poll_requests"]) == (
        metrics["polls"],
        metrics["last_poll_requests"],
    )
    assert client._plan is plan


async def test_export_points_round_trips(
    hass: HomeAssistant, setup_integration: MockConfigEntry
) -> None:
    """export_points gives the import format back: importing it gives the same points."""
    response = await hass.services.async_call(
        DOMAIN,
        "export_points",
        {"config_entry_id": setup_integration.entry_id},
        blocking=True,
        return_response=True,
    )
    assert response is not None
    assert set(response["devices"]) == {"S7-200 SMART"}
    points, errors = parse_points(S7SmartClient, str(response["points"]))
    assert errors == []
    assert points == sorted((data for _, data in POINTS), key=point_order)
