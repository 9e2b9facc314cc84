"""The base entity of PLC Bridge and the point description built from a configured point."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from enum import StrEnum
from functools import lru_cache
from typing import Any

from homeassistant.const import CONF_HOST, CONF_PORT
from homeassistant.core import HomeAssistant, callback
from homeassistant.helpers import device_registry as dr, entity_registry as er
from homeassistant.helpers.device_registry import CONNECTION_NETWORK_MAC, DeviceInfo, format_mac
from homeassistant.helpers.entity import EntityDescription
from homeassistant.helpers.update_coordinator import BaseCoordinatorEntity, CoordinatorEntity
from yarl import URL

from .const import CONF_MAC, CONF_TLS, DOMAIN
from .coordinator import PlcBridgeConfigEntry, PlcCoordinator
from .model.availability import POLICY_DATA_VALID, POLICY_KEEP, has_data_valid, policy_of
from .model.conversion import Conversion
from .model.points import PointConfig
from .plc import PlcError, Point, PointResult, TlsMode, Value, ValueKind
from .runtime.restore import restored_result

MANUFACTURERS = {
    "s7_smart": "Siemens",
    "s7": "Siemens",
    "tecomat": "Teco",
    "plcnext": "Phoenix Contact",
    "softplc": "SoftPLC",
}


@dataclass(frozen=True, kw_only=True)
class PlcPointDescription(EntityDescription):
    """One point as an entity: its address and type, what it holds, and its conversion."""

    point: Point
    kind: ValueKind | None = None
    scale: float = 1.0
    offset: float = 0.0
    read_only: bool = False
    conversion: Conversion | None = None
    """The point's conversions; None: scale and offset alone."""

    @property
    def convert(self) -> Conversion:
        """The point's conversions (scale and offset where no other was given)."""
        return self.conversion or Conversion(scale=self.scale, offset=self.offset)

    def value_fn(self, raw: Value | None) -> Any:
        """Return what Home Assistant shows for a raw value: numbers converted, bytes as hex."""
        if isinstance(raw, bool):
            return raw
        if isinstance(raw, int | float):
            return self.convert.shown(raw)
        if isinstance(raw, list):
            return " ".join(f"{byte:02X}" for byte in raw)
        return raw

    def raw_fn(self, value: float) -> int | float:
        """Return the raw value to write for a shown number (conversion inverted)."""
        return self.convert.raw(value, integer=self.kind is ValueKind.INTEGER)


def entity_name(entry: PlcBridgeConfigEntry, subentry_id: str, name: str) -> str | None:
    """Return an entity's name; None where it is its machine's (the machine's main feature).

    Home Assistant then names it after the device: "Pump", not "Pump Pump".
    """
    subentry = entry.subentries.get(subentry_id)
    same = subentry is not None and subentry.title.strip().casefold() == name.strip().casefold()
    return None if same else name


def point_kind(entry: PlcBridgeConfigEntry, point: Point) -> ValueKind | None:
    """Return what a point's value is; None where its address is not understood."""
    try:
        return entry.runtime_data.client.value_kind(point)
    except PlcError:
        return None  # the poll reports the address error on the entity


def point_fields(entry: PlcBridgeConfigEntry, config: PointConfig) -> dict[str, Any]:
    """Return the PlcPointDescription fields of a configured point."""
    conversion = config.conversion
    return {
        "key": config.point_id,
        "name": entity_name(entry, config.subentry_id, config.name),
        "point": config.point,
        "kind": point_kind(entry, config.point),
        "scale": conversion.scale,
        "offset": conversion.offset,
        "read_only": config.read_only,
        "conversion": conversion,
    }


def device_class[E: StrEnum](config: PointConfig, enum: type[E]) -> E | None:
    """Return the point's device class if the platform knows it."""
    try:
        return None if config.device_class is None else enum(config.device_class)
    except ValueError:
        return None


@callback
def async_remove_entity(
    hass: HomeAssistant, entry: PlcBridgeConfigEntry, platform: str, key: str
) -> None:
    """Remove a PLC entity this setup no longer makes, so it is not left behind unavailable."""
    registry = er.async_get(hass)
    entity_id = registry.async_get_entity_id(platform, DOMAIN, f"{device_key(entry)}_{key}")
    if entity_id is not None:
        registry.async_remove(entity_id)


def device_key(entry: PlcBridgeConfigEntry) -> str:
    """Return what identifies the PLC's device and entities for as long as the entry exists.

    The unique id where the PLC reports a serial or MAC (it is that); else the entry id, as the
    unique id is then host:port and changes when the PLC is moved with Reconfigure. An entry made
    by address stays keyed by its id when a new firmware starts reporting a serial.
    """
    device = entry.runtime_data.device
    address = f"{entry.data.get(CONF_HOST)}:{entry.data.get(CONF_PORT)}"
    if (device.serial or device.mac) and entry.unique_id not in (None, address):
        return str(entry.unique_id)
    return entry.entry_id


def web_page(entry: PlcBridgeConfigEntry) -> str | None:
    """Return the address of the PLC's web server that Home Assistant talks to, if it has one."""
    if not entry.runtime_data.client.uses_http:
        return None
    secure = entry.data.get(CONF_TLS, TlsMode.NONE) != TlsMode.NONE
    url = URL.build(
        scheme="https" if secure else "http",
        host=entry.data[CONF_HOST],
        port=int(entry.data[CONF_PORT]),
        path="/",
    )
    return str(url)


def device_info(entry: PlcBridgeConfigEntry) -> DeviceInfo:
    """Return the device of a PLC, from what it said when it connected."""
    device = entry.runtime_data.device
    mac = device.mac or entry.data.get(CONF_MAC)  # else the one its discovery saw
    connections = {(CONNECTION_NETWORK_MAC, format_mac(mac))} if mac else set()
    return DeviceInfo(
        identifiers={(DOMAIN, device_key(entry))},
        name=entry.title,
        manufacturer=MANUFACTURERS.get(device.vendor, device.vendor),
        model=str(device.model),
        sw_version=str(device.firmware) if device.firmware else None,
        serial_number=str(device.serial) if device.serial else None,
        connections=connections,
        configuration_url=web_page(entry),
    )


@lru_cache(maxsize=4096)
def device_of(identifier: str) -> DeviceInfo:
    """Return the device info naming one device: one object for every entity of the device.

    Home Assistant only reads it (to find the device when an entity is added).
    """
    return DeviceInfo(identifiers={(DOMAIN, identifier)})


def plc_device(hass: HomeAssistant, entry: PlcBridgeConfigEntry) -> str:
    """Return the id of the PLC's own device, made or brought up to date."""
    registry = dr.async_get(hass)
    return registry.async_get_or_create(config_entry_id=entry.entry_id, **device_info(entry)).id


def entity_policy(entry: PlcBridgeConfigEntry, subentry_id: str, policy: str | None) -> str:
    """Return the availability policy a point stores (or None) gives its entity on its machine."""
    machine = entry.subentries.get(subentry_id)
    data_valid = machine is not None and has_data_valid(machine.data)
    return policy_of(policy, data_valid=data_valid)


class PlcEntity(CoordinatorEntity[PlcCoordinator]):
    """An entity of one PLC's device: unique id and device set once.

    An entity of points shows the values its PLC kept at the last stop (runtime/restore.py),
    marked restored, until a poll reads its points; they are seen only while its state is
    written (`_showing`), so no command is ever decided from them.
    """

    _attr_has_entity_name = True
    _policy: str = POLICY_DATA_VALID
    """The availability policy (model/availability.py); the PLC's own entities follow the PLC."""
    _restored: Mapping[str, Any] | None = None
    """The raw values by point kept at the last stop, until a poll reads every point."""
    _restores = True
    """False where the platform restores its own state (an event its last event)."""
    _showing = False
    _shown_note: str | None = None

    def __init__(self, entry: PlcBridgeConfigEntry, key: str, point: Point | None = None) -> None:
        """Attach the entity to the entry's coordinator (for `point`) and the PLC's device."""
        super().__init__(entry.runtime_data.coordinator, context=point)
        self._attr_unique_id = f"{device_key(entry)}_{key}"
        self._attr_device_info = device_of(device_key(entry))
        self._shown_available: bool | None = None  # None: nothing shown yet
        self._shown: Any = None
        self._machine: str | None = None  # the device subentry whose availability applies

    @property
    def held(self) -> bool:
        """True while the PLC cannot be reached and the entity keeps showing its last values."""
        return self._policy == POLICY_KEEP and not self.coordinator.last_update_success

    @property
    def available(self) -> bool:
        """Available while the PLC answers (or its values are kept) and its data valid, if asked."""
        if not super().available:
            return self.held
        return (
            self._policy != POLICY_DATA_VALID
            or self._machine not in self.coordinator.availability.invalid
        )

    @property
    def extra_state_attributes(self) -> dict[str, Any] | None:
        """Say that values are restored, or when the values kept were read."""
        if self._restored is not None:
            return {"restored": True}
        if self.held and (read_at := self.coordinator.availability.read_at) is not None:
            return {"last_read": read_at.isoformat()}
        return None

    def restored_points(self) -> list[Point]:
        """The points whose kept values the entity shows before they are read: those it shows."""
        return self.read_points() if self._restores else []

    def point_result(self, point: Point) -> PointResult | None:
        """A point's outcome in the last poll; while shown before its first read, its restored."""
        result = self.coordinator.data.values.get(point)
        if result is None and self._showing:
            return restored_result(self._restored, point)
        return result

    def _note(self) -> str | None:
        """What the attributes say beside the state: restored, kept, or nothing."""
        return "restored" if self._restored is not None else "held" if self.held else None

    @callback
    def _async_write_ha_state(self) -> None:
        """Write the state, restored values included where no poll has read their point yet."""
        self._showing = True
        try:
            super()._async_write_ha_state()
        finally:
            self._showing = False

    def observed(self) -> Any:
        """What this entity shows of the last poll; its state is written only when this changes."""
        raise NotImplementedError

    def read_points(self) -> list[Point]:
        """The points this entity shows."""
        return [self.coordinator_context] if self.coordinator_context is not None else []

    async def async_update(self) -> None:
        """Poll now (`homeassistant.update_entity`), reading this entity's points whatever class."""
        self.coordinator.ask_back(self.read_points())
        await super().async_update()

    async def async_added_to_hass(self) -> None:
        """Follow the coordinator's polls; restore what is not read yet; note the first state.

        Values kept at the last stop are taken for the points not read yet. The coordinator's
        one dispatch updates the entity: the base's listener would keep a callback, a remover
        and their arguments per entity.
        """
        await super(BaseCoordinatorEntity, self).async_added_to_hass()
        self.coordinator.async_follow(self, self.coordinator_context)
        stored = self.registry_entry
        if stored is not None and stored.unique_id == self._attr_unique_id:
            self._attr_unique_id = stored.unique_id  # the registry's string: one for both
        read = self.coordinator.data.values
        if unread := [point for point in self.restored_points() if point not in read]:
            self._restored = self.coordinator.stored.restored_for(unread)
        self._shown_available, self._shown, self._shown_note = self._shown_now()

    def _shown_now(self) -> tuple[bool, Any, str | None]:
        """Return the availability, what is observed and the note as the state would show them."""
        self._showing = True
        try:
            return self.available, self.observed(), self._note()
        finally:
            self._showing = False

    async def async_will_remove_from_hass(self) -> None:
        """Stop following the coordinator."""
        self.coordinator.async_unfollow(self)
        await super().async_will_remove_from_hass()

    @callback
    def _handle_coordinator_update(self) -> None:
        """Write the state only when availability or the value changed: a quiet poll writes none."""
        if self._restored is not None:
            read = self.coordinator.data.values
            if all(point in read for point in self.restored_points()):
                self._restored = None
        available, shown, note = self._shown_now()
        if (
            available != self._shown_available
            or note != self._shown_note
            or not (shown is self._shown or shown == self._shown)
        ):
            self._shown_available, self._shown, self._shown_note = available, shown, note
            super()._handle_coordinator_update()


class PlcPointEntity(PlcEntity):
    """An entity showing one point; unavailable while its point fails, whatever the others do."""

    entity_description: PlcPointDescription

    def __init__(
        self, entry: PlcBridgeConfigEntry, config: PointConfig, description: PlcPointDescription
    ) -> None:
        """Bind the entity to its point and device (the key: the point id, or it and a bit)."""
        super().__init__(entry, description.key, description.point)
        self._attr_device_info = device_of(config.subentry_id)
        self._machine = config.subentry_id
        self._policy = entity_policy(entry, config.subentry_id, config.availability)
        self.entity_description = description

    @property
    def result(self) -> PointResult | None:
        """The point's outcome in the last poll (restored where shown before its first read)."""
        return self.point_result(self.entity_description.point)

    @property
    def available(self) -> bool:
        """Available while the PLC answers and this point reads without error."""
        result = self.result
        return super().available and result is not None and result.ok

    @property
    def raw_value(self) -> Value | None:
        """The point's value as the PLC sent it."""
        result = self.result
        return result.value if result is not None else None

    def observed(self) -> Any:
        """The point's value as read in the last poll."""
        return self.raw_value

    async def async_write(self, value: Value) -> None:
        """Write the point (one request), then refresh; the coordinator's write guard checks it."""
        await self.coordinator.async_write({self.entity_description.point: value})
