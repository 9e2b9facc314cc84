"""The poll cadence's one override of DataUpdateCoordinator, checked on each harness.

runtime/polling.py replaces the base's private scheduler (`_schedule_refresh`) to count an
interval from the start of a poll. It relies on the base members BASE_MEMBERS names: this
file runs on the current and on the oldest supported Home Assistant, so a release that renames
one fails here rather than in a poll.
"""

from __future__ import annotations

import ast
from datetime import timedelta
import inspect
import logging
import textwrap
from typing import Any, cast

from homeassistant.core import HomeAssistant
from homeassistant.helpers.update_coordinator import (
    BaseCoordinatorEntity,
    DataUpdateCoordinator,
    UpdateFailed,
)
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import DOMAIN
from custom_components.plc_bridge.plc import PlcClient, ReadResult
from custom_components.plc_bridge.runtime.polling import BASE_MEMBERS, PollingCoordinator


class Refused(PollingCoordinator):
    """A coordinator whose every poll fails, asking for a retry after 30 s."""

    async def _async_update_data(self) -> ReadResult:
        """Fail as a PLC that asks to be left alone would."""
        raise UpdateFailed("busy", retry_after=30.0)


@pytest.mark.parametrize("member", BASE_MEMBERS)
async def test_the_base_members_the_cadence_relies_on_exist(
    hass: HomeAssistant, member: str
) -> None:
    """Each private member of the contract is on Home Assistant's coordinator."""
    coordinator: DataUpdateCoordinator[Any] = DataUpdateCoordinator(
        hass,
        logging.getLogger(__name__),
        config_entry=None,
        name="x",
        update_interval=timedelta(seconds=5),
    )
    assert hasattr(coordinator, member)
    if member == "_schedule_refresh":
        assert callable(getattr(DataUpdateCoordinator, member))


async def test_a_retry_after_puts_the_next_poll_off(hass: HomeAssistant) -> None:
    """An UpdateFailed naming retry_after is honoured: the next poll waits for it, not 5 s."""
    entry = MockConfigEntry(domain=DOMAIN, title="PLC", data={})
    entry.add_to_hass(hass)
    coordinator = Refused(hass, entry, cast(PlcClient, object()))
    coordinator.update_interval = timedelta(seconds=5)
    remove = coordinator.async_add_listener(lambda: None)
    await coordinator.async_refresh()
    assert not coordinator.last_update_success
    assert coordinator._due is not None
    assert coordinator._due - hass.loop.time() > 25
    remove()
    await coordinator.async_shutdown()


def test_the_base_entity_only_listens_when_added() -> None:
    """PlcEntity skips BaseCoordinatorEntity.async_added_to_hass: it only adds the listener.

    The coordinator's one dispatch replaces that listener (entity.py); a release that does more
    there fails here.
    """
    source = textwrap.dedent(inspect.getsource(BaseCoordinatorEntity.async_added_to_hass))
    function = ast.parse(source).body[0]
    assert isinstance(function, ast.AsyncFunctionDef)
    body = [
        node
        for node in function.body
        if not isinstance(node, ast.Expr) or not isinstance(node.value, ast.Constant)
    ]
    assert len(body) == 2
    assert "super().async_added_to_hass()" in ast.unparse(body[0])
    assert "self.async_on_remove(self.coordinator.async_add_listener(" in ast.unparse(body[1])
