"""What a loaded PLC entry keeps, and the typed config entry every module takes."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from homeassistant.config_entries import ConfigEntry

from .plc import DeviceInfo, PlcClient

if TYPE_CHECKING:
    from .coordinator import PlcCoordinator
    from .points import PointEntities


@dataclass(slots=True, kw_only=True)
class PlcRuntimeData:
    """What a loaded entry keeps: the connected client, its coordinator, what the PLC said."""

    client: PlcClient
    coordinator: PlcCoordinator
    device: DeviceInfo
    points: PointEntities
    settings: tuple[dict[str, Any], dict[str, Any]]
    """The entry's data and options at setup: a change of these reloads the entry."""


type PlcBridgeConfigEntry = ConfigEntry[PlcRuntimeData]
