"""The base of entities built from several points: each part read, shown and written alone.

A part whose read fails shows as unknown while the others keep showing; the entity is
unavailable only when the PLC does not answer or none of its parts reads. Commands write
their point's "on" value once, or pulse it (outputs.py: on, then off after the point's pulse
time whatever the on's outcome, the off retried until confirmed and ended at unload or stop).
"""

from __future__ import annotations

import asyncio
from collections.abc import Callable, Collection, Iterable
from dataclasses import dataclass
from typing import Any

from homeassistant.components.climate import ClimateEntity
from homeassistant.const import UnitOfTemperature
from homeassistant.core import callback
from homeassistant.exceptions import HomeAssistantError, ServiceValidationError
from homeassistant.helpers.entity import Entity
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from .const import DOMAIN
from .coordinator import PlcBridgeConfigEntry
from .entity import PlcEntity, device_of, entity_name, entity_policy, point_kind
from .model.composite import Composite, composites, group_key
from .model.conversion import Conversion
from .model.kinds import KINDS
from .model.points import PointConfig
from .plc import Point, PointResult, Value, ValueKind
from .runtime.entities import PointFactory
from .runtime.issues import COMMAND_NOT_RELEASED, PULSE_FAILED
from .runtime.outputs import Output, async_send
from .runtime.supervision import Supervisor, seconds_of


@dataclass(frozen=True, slots=True)
class Part:
    """One point of a composite entity: its configuration and the kind of value it holds."""

    config: PointConfig
    kind: ValueKind | None

    @property
    def point(self) -> Point:
        """The part's address and data type."""
        return self.config.point

    @property
    def conversion(self) -> Conversion:
        """How the part's raw value converts to what is shown."""
        return self.config.conversion

    @property
    def pulse(self) -> float:
        """The part's pulse in seconds; 0 for a level or a single write."""
        return self.config.pulse_seconds

    @property
    def read_only(self) -> bool:
        """True when Home Assistant must never write the part."""
        return self.config.read_only

    def level(self, *, on: bool) -> bool | int | float:
        """Return the raw value that means on or off for this part (codes and invert applied)."""
        return self.conversion.state_value(on, boolean=self.kind is ValueKind.BOOL)

    @property
    def limits(self) -> tuple[float | None, float | None, float | None]:
        """A set point's lowest and highest value and step: its min, max, step, else its range."""
        config, bounds = self.config, self.conversion.bounds
        low = None if config.min is None else float(config.min)
        high = None if config.max is None else float(config.max)
        if bounds:
            low = bounds[0] if low is None else low
            high = bounds[1] if high is None else high
        return low, high, float(config.step) if config.step else None


def temperature_unit(parts: Iterable[Part]) -> str:
    """The unit of an entity's temperatures: Fahrenheit where a part says so, else Celsius."""
    units = {part.config.unit_of_measurement for part in parts}
    fahrenheit = UnitOfTemperature.FAHRENHEIT in units
    return UnitOfTemperature.FAHRENHEIT if fahrenheit else UnitOfTemperature.CELSIUS


def part_of(entry: PlcBridgeConfigEntry, config: PointConfig) -> Part:
    """Return a configured point as a part."""
    return Part(config, point_kind(entry, config.point))


type CompositeFactory = Callable[[PlcBridgeConfigEntry, Composite, dict[str, Part]], Entity]


def async_setup_composites(
    entry: PlcBridgeConfigEntry,
    platform: str,
    factory: CompositeFactory,
    add: AddConfigEntryEntitiesCallback,
    single: PointFactory | None = None,
) -> None:
    """Register a composite platform: one entity per group, made for the group's first point.

    `single` makes the entity of a point of the platform that is no part (a plain switch).
    """

    def make(entry: PlcBridgeConfigEntry, config: PointConfig) -> Entity | list[Entity]:
        """Return the entity of the group this point leads; none for its other points."""
        if group_key(config) is None:
            return [] if single is None else single(entry, config)
        group = composites(entry.runtime_data.points.configs).get(config.point_id)
        if group is None:
            return []
        parts = {role: part_of(entry, member) for role, member in group.parts.items()}
        return [factory(entry, group, parts)]

    entry.runtime_data.points.async_setup_platform(platform, make, add)


def own_class(platform: str, parts: dict[str, Part]) -> str | None:
    """Return the entity's device class: a part's that is one of its kind's (a shutter)."""
    kind = KINDS[platform]
    found = (kind.own_class(part.config.device_class) for part in parts.values())
    own = next((name for name in found if name), "")
    return kind.device_class(own) if kind.device_class is not None and own else None


class PlcCompositeEntity(PlcEntity):
    """An entity of several points of one device, named by the rows it was built from."""

    def __init__(
        self, entry: PlcBridgeConfigEntry, group: Composite, parts: dict[str, Part]
    ) -> None:
        """Bind the entity to its parts and to its device subentry's device."""
        super().__init__(entry, group.key)
        self._attr_name = entity_name(entry, group.subentry_id, group.name)
        self._label = group.name  # what messages call it, whatever Home Assistant shows
        self._attr_device_info = device_of(group.subentry_id)
        self._machine = group.subentry_id
        stated = [p.config.availability for p in parts.values() if p.config.availability]
        self._policy = entity_policy(entry, group.subentry_id, stated[0] if stated else None)
        self.parts = parts
        self._key = group.key
        self._platform = group.platform
        self._writing = asyncio.Lock()  # one write of commands and releases at a time
        self.outputs = {role: self._output(role) for role, part in parts.items() if part.pulse > 0}
        seconds = seconds_of(part.config.supervision for part in parts.values())
        self.supervisor = Supervisor(entry, self._key, self._label, seconds, self.follows)
        if (own := own_class(group.platform, parts)) is not None:
            self._attr_device_class = own

    def features(self) -> int:
        """The entity features its kind's description gives the parts it has, as flags.

        A part enables its role's features where Home Assistant writes it: a role that is
        always written (a command, a set point), or one read and written unless read only.
        """
        kind = KINDS[self._platform]
        return kind.features(
            role
            for role, part in self.parts.items()
            if not part.read_only or ((described := kind.role(role)) and described.written)
        )

    def _output(self, role: str) -> Output:
        """Return the output of a command part: its off-write and its repair issue."""
        part = self.parts[role]
        kind = PULSE_FAILED if part.pulse > 0 else COMMAND_NOT_RELEASED
        off = {part.point: part.level(on=False)}
        return Output(
            self.coordinator.config_entry,
            self._writing,
            (kind, f"{self._key}_{role}"),
            name=f"{self._label} ({role})",
            address=part.point.address,
            write_off=lambda: async_send(self.coordinator, off, release=True),
            read_back=self._read_back_later,
        )

    @callback
    def _read_back_later(self) -> None:
        """Have the parts read back by a poll soon, without waiting for it."""
        self.coordinator.ask_back(self.read_points())
        self.coordinator.config_entry.async_create_background_task(
            self.hass, self.coordinator.async_request_refresh(), f"{self._label} read back"
        )

    async def _async_read_back(self) -> None:
        """Have the parts read back now, whatever their class."""
        self.coordinator.ask_back(self.read_points())
        await self.coordinator.async_request_refresh()

    def read_points(self) -> list[Point]:
        """The points of the entity's parts."""
        return [part.point for part in self.parts.values()]

    def result(self, role: str) -> PointResult | None:
        """A part's outcome in the last poll (restored if shown before its first read), or None."""
        part = self.parts.get(role)
        return None if part is None else self.point_result(part.point)

    def raw(self, role: str) -> Value | None:
        """A part's raw value; None without the part or while its read fails."""
        result = self.result(role)
        return result.value if result is not None and result.ok else None

    def number(self, role: str) -> float | None:
        """A part's value converted to what is shown; None where it has none."""
        raw = self.raw(role)
        if isinstance(raw, bool) or not isinstance(raw, int | float):
            return None
        return self.parts[role].conversion.shown(raw)

    def label(self, role: str) -> str | None:
        """The label of a part's value in its value map; None where it has none."""
        part = self.parts.get(role)
        return None if part is None else part.conversion.label(self.raw(role))

    def on(self, role: str) -> bool | None:
        """Whether a part reads as on (its codes and invert applied); None where unknown."""
        part = self.parts.get(role)
        return None if part is None else part.conversion.is_on(self.raw(role))

    @property
    def available(self) -> bool:
        """Available while the PLC answers and at least one part reads."""
        return super().available and any(
            (result := self.result(role)) is not None and result.ok for role in self.parts
        )

    def observed(self) -> Any:
        """Every part's outcome in the last poll."""
        return tuple(self.result(role) for role in sorted(self.parts))

    async def async_write_parts(self, values: dict[str, Value]) -> None:
        """Write parts by role in one request (the write guard checks each); read all parts back."""
        await self.coordinator.async_write(
            {self.parts[role].point: values[role] for role in values}, read_back=self.read_points()
        )

    async def async_write_number(self, role: str, value: float, low: float, high: float) -> None:
        """Write a part's shown value through its conversion; refused outside low..high first."""
        if not low <= value <= high:
            raise ServiceValidationError(
                translation_domain=DOMAIN,
                translation_key="out_of_range",
                translation_placeholders={
                    "value": f"{value:g}",
                    "min": f"{low:g}",
                    "max": f"{high:g}",
                },
            )
        part = self.parts[role]
        await self.async_write_parts(
            {role: part.conversion.raw(value, integer=part.kind is ValueKind.INTEGER)}
        )

    async def async_command(
        self, role: str, *, hold: float = 0.0, release: Collection[str] = ()
    ) -> None:
        """Send a command part's "on", its `release` parts' "off" in the same write.

        A pulse's off follows after its time; a level with an output (`hold` seconds at most)
        is released by its entity. Either way whatever the on-write's outcome.
        """
        part = self.parts[role]
        values = {role: part.level(on=True)}
        values |= {other: self.parts[other].level(on=False) for other in release}
        points = {self.parts[key].point: value for key, value in values.items()}
        output = self.outputs.get(role)
        try:
            if output is None:
                async with self._writing:
                    await async_send(self.coordinator, points, release=bool(release))
            elif not await output.async_turn_on(
                lambda: async_send(self.coordinator, points, release=bool(release)),
                part.pulse or hold,
                again=not part.pulse,
            ):
                return
        except ServiceValidationError:
            raise
        except HomeAssistantError:
            for other in release:
                if (released := self.outputs.get(other)) is not None:
                    released.unconfirmed()
            raise
        for other in release:
            if (released := self.outputs.get(other)) is not None:
                released.released()
        await self._async_read_back()

    def follows(self, commanded: str) -> bool | None:
        """Whether the state shown is what was commanded ("on" or "off"); None while unknown."""
        state: bool | None = getattr(self, "is_on", None)
        return None if state is None else state == (commanded == "on")

    @callback
    def _handle_coordinator_update(self) -> None:
        """Check the state watched by the supervision, then show the poll."""
        self.supervisor.update()
        super()._handle_coordinator_update()

    def switched(self) -> bool | None:
        """On or off: the `state` part, else what a level `command` part reads back."""
        if "state" in self.parts:
            return self.on("state")
        command = self.parts.get("command")
        return None if command is None or command.pulse else self.on("command")

    async def async_switch(self, on: bool, also: dict[str, Value] | None = None) -> None:
        """Switch on or off (with `also` written first): a level, or a pulse when the state differs.

        An impulse relay toggles with each pulse, so a pulse is sent only when the state read
        is the other one; with the state unknown nothing is sent.
        """
        values = dict(also or {})
        command = self.parts.get("command")
        if command is None or not command.pulse:
            if command is not None:
                values["command"] = command.level(on=on)
            if values:
                await self.async_write_parts(values)
            self.supervisor.watch("on" if on else "off")
            return
        state = self.on("state")
        if state is None:
            raise HomeAssistantError(
                translation_domain=DOMAIN,
                translation_key="state_unknown",
                translation_placeholders={"name": self._label},
            )
        if values:
            await self.async_write_parts(values)
        if state != on:
            await self.async_command("command")
        self.supervisor.watch("on" if on else "off")

    async def async_added_to_hass(self) -> None:
        """Follow Home Assistant's stop for every output; release what a last setup left on."""
        await super().async_added_to_hass()
        for output in self.outputs.values():
            self.async_on_remove(output.async_attach(self.hass))
        self.async_on_remove(self.supervisor.async_attach(self))

    async def async_will_remove_from_hass(self) -> None:
        """Removed (unload, reload, edit): release every output still held, now."""
        for output in self.outputs.values():
            await output.async_end()
        await super().async_will_remove_from_hass()


NATIVE_TEMPERATURES = hasattr(ClimateEntity, "native_current_temperature")
"""Home Assistant 2026.11 reads climate and water heater temperatures as `native_*`; the old
names go in 2027.11. Both took the new names in the same release."""


class PlcTemperatureEntity(PlcCompositeEntity):
    """A climate entity or water heater: its temperature parts, limits and unit.

    Under the names the running Home Assistant reads (`native_*` from 2026.11).
    """

    _attr_min_temp: float
    _attr_max_temp: float
    _attr_target_temperature_step: float | None
    _attr_native_temperature_unit: str
    _attr_temperature_unit: str

    def set_temperature_limits(self, parts: dict[str, Part]) -> None:
        """Take the unit from the parts and the target's limits and step from its point."""
        unit = temperature_unit(parts.values())
        if NATIVE_TEMPERATURES:
            self._attr_native_temperature_unit = unit
        else:
            self._attr_temperature_unit = unit
        if (target := parts.get("target_temperature")) is not None:
            low, high, step = target.limits
            if low is not None:
                self._attr_min_temp = low
            if high is not None:
                self._attr_max_temp = high
            if step is not None:
                self._attr_target_temperature_step = step

    @property
    def native_current_temperature(self) -> float | None:
        """The temperature read, in its part's unit."""
        return self.number("current_temperature")

    @property
    def native_target_temperature(self) -> float | None:
        """The set temperature read back, in its part's unit."""
        return self.number("target_temperature")

    if not NATIVE_TEMPERATURES:

        @property
        def current_temperature(self) -> float | None:
            """The temperature read (what Home Assistant before 2026.11 reads)."""
            return self.native_current_temperature

        @property
        def target_temperature(self) -> float | None:
            """The set temperature read back (what Home Assistant before 2026.11 reads)."""
            return self.native_target_temperature
