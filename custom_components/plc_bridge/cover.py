"""Covers built from several points: commands, position, limit switches or a status map.

Roles (one point each, every one optional, one at least): `open`, `close`, `stop` (commands
written as a level or a pulse), `position` (read, 0-100 % through the point's linear range;
written too unless read only and no `set_position` is given), `set_position`, `open_limit`
and `closed_limit` (limit switches), `status` (a value map onto open, closed, opening,
closing), `tilt_position` and `set_tilt_position` (as the position), `step` (one step-relay
button: open, close and stop each send its pulse). `invert` on a position point makes 0 %
open. Without open or close commands, a settable position opens to 100 % and closes to 0 %.

Commands written as levels are interlocked and always released (outputs.py): each command
writes its own "on" and the other commands' "off" in one write, so open and close are never
asked for at once. Open (close) is released once the open (closed) end is read reached, by
the limit switch, the position at 100 % (0 %) or the status map, in a poll after the command;
or after the group's `travel_time` (seconds), DEFAULT_TRAVEL_TIME without one. A level stop
is released after STOP_HOLD. A position written releases the level commands still held.
"""

from __future__ import annotations

from typing import Any

from homeassistant.components.cover import (
    ATTR_POSITION,
    ATTR_TILT_POSITION,
    CoverEntity,
    CoverEntityFeature,
)
from homeassistant.core import HomeAssistant, callback
from homeassistant.helpers.entity_platform import AddConfigEntryEntitiesCallback

from .composite_entity import Part, PlcCompositeEntity, async_setup_composites
from .coordinator import PlcBridgeConfigEntry
from .model.composite import Composite
from .plc import Point, Value, ValueKind
from .runtime.outputs import async_send
from .runtime.supervision import seconds_of

PARALLEL_UPDATES = 1
FULL = 100
COMMANDS = ("open", "close", "stop")
"""The command roles that interlock: each one written releases the others."""
DEFAULT_TRAVEL_TIME = 60.0
"""Seconds after which a level open or close is released when no travel time is set."""
STOP_HOLD = 2.0
"""Seconds a level stop is held: seen by any PLC scan, short enough not to block a move."""


async def async_setup_entry(
    hass: HomeAssistant,
    entry: PlcBridgeConfigEntry,
    async_add_entities: AddConfigEntryEntitiesCallback,
) -> None:
    """Add a cover for each group of cover points."""
    async_setup_composites(entry, "cover", PlcCover, async_add_entities)


def travel_time(parts: dict[str, Part]) -> float:
    """Return the group's travel time in seconds: its parts' `travel_time`, else the default."""
    seconds = seconds_of(part.config.travel_time for part in parts.values())
    return DEFAULT_TRAVEL_TIME if seconds is None else seconds


class Travel(PlcCompositeEntity):
    """What covers and valves share: commands, a position, limit switches, a status map."""

    def __init__(
        self, entry: PlcBridgeConfigEntry, group: Composite, parts: dict[str, Part]
    ) -> None:
        """Give each command part its output; a level open or close travels this long at most."""
        super().__init__(entry, group, parts)
        self._commands = [role for role in COMMANDS if role in parts and not parts[role].read_only]
        for role in self._commands:
            self.outputs.setdefault(role, self._output(role))
        self._travel_time = travel_time(parts)
        self.supervisor.seconds = seconds_of(p.config.travel_time for p in parts.values())
        self._moved: dict[str, float] = {}  # level open or close held: loop time of its command
        self._left: set[str] = set()  # of those, the ones read away from their end since

    def _setter(self, role: str = "position") -> str | None:
        """The role that takes a position: `set_position`, else a writable `position`."""
        if f"set_{role}" in self.parts:
            return f"set_{role}"
        position = self.parts.get(role)
        return role if position is not None and not position.read_only else None

    def _inverted(self, role: str) -> bool:
        """True when the part counts 0 as open."""
        return self.parts[role].conversion.invert

    def _position(self, role: str = "position") -> int | None:
        """The position read, 0 closed to 100 open."""
        value = self.number(role)
        if value is None:
            return None
        position = round(min(max(value, 0), FULL))
        return FULL - position if self._inverted(role) else position

    @property
    def is_closed(self) -> bool | None:
        """Closed by the closed limit, the status map, or a position of 0; None if unknown."""
        return self._closed()

    @property
    def is_opening(self) -> bool:
        """True while the status map says opening."""
        return self.label("status") == "opening"

    @property
    def is_closing(self) -> bool:
        """True while the status map says closing."""
        return self.label("status") == "closing"

    def _closed(self) -> bool | None:
        """Closed by the closed limit, the status map, or a position of 0; None if unknown."""
        if self.on("closed_limit"):
            return True
        if self.on("open_limit"):
            return False
        if "closed_limit" in self.parts and self.on("closed_limit") is False:
            return False
        if (status := self.label("status")) is not None:
            return status == "closed"
        position = self._position()
        return None if position is None else position == 0

    def _reached(self, role: str) -> bool | None:
        """Whether the end `role` moves to reads reached; None where no part tells."""
        limit, status, end = (
            ("open_limit", "open", FULL) if role == "open" else ("closed_limit", "closed", 0)
        )
        readings: list[bool] = []
        if (on := self.on(limit)) is not None:
            readings.append(on)
        if (label := self.label("status")) is not None:
            readings.append(label == status)
        if (position := self._position()) is not None:
            readings.append(position == end)
        return None if not readings else any(readings)

    @callback
    def _handle_coordinator_update(self) -> None:
        """Release a level open or close once a poll after its command reads its end reached.

        An end that already read reached when the command was given counts once it was read
        left, or once a poll interval passed (a fresh poll read it still reached).
        """
        now = self.hass.loop.time()
        interval = self.coordinator.update_interval
        tick = interval.total_seconds() if interval is not None else 0.0
        for role, since in list(self._moved.items()):
            output = self.outputs[role]
            if not output.held:
                del self._moved[role]
                self._left.discard(role)
                continue
            reached = self._reached(role)
            if reached is False:
                self._left.add(role)
            elif reached and (role in self._left or now - since >= tick):
                output.release_soon()
        super()._handle_coordinator_update()

    async def _async_move(self, role: str, position: int | None) -> None:
        """Send the command, else a step relay's pulse, else move to the position."""
        if role in self.parts:
            release = [other for other in self._commands if other != role]
            level = not self.parts[role].pulse and role in self._commands
            if level and role != "stop":
                self._moved[role] = self.hass.loop.time()
                self._left.discard(role)
            hold = STOP_HOLD if role == "stop" else self._travel_time
            await self.async_command(role, hold=hold, release=release)
        elif "step" in self.parts:
            await self.async_command("step")
        elif position is not None:
            await self._async_set_position(position)
        self.supervisor.watch(role if role in ("open", "close") else None)

    def follows(self, commanded: str) -> bool | None:
        """Whether the end an open or close moves to reads reached; None where no part tells."""
        return self._reached(commanded)

    async def _async_set_position(self, position: float, which: str = "position") -> None:
        """Write the position through the part's range (refused outside it, nothing sent)."""
        role = self._setter(which)
        if role is None:
            return
        part = self.parts[role]
        if self._inverted(role):
            position = FULL - position
        raw = part.conversion.raw(position, integer=part.kind is ValueKind.INTEGER)
        held = [other for other in self._commands if self.outputs[other].held]
        self.supervisor.watch(None)
        if not held:
            await self.async_write_parts({role: raw})
            return
        values: dict[Point, Value] = {part.point: raw}
        values |= {self.parts[other].point: self.parts[other].level(on=False) for other in held}
        async with self._writing:
            await async_send(self.coordinator, values, release=True)
        for other in held:
            self.outputs[other].released()
        await self._async_read_back()


class PlcCover(Travel, CoverEntity):
    """A cover whose parts are points of one machine."""

    def __init__(
        self, entry: PlcBridgeConfigEntry, group: Composite, parts: dict[str, Part]
    ) -> None:
        """Work out what the cover can do from the parts it has."""
        super().__init__(entry, group, parts)
        self._attr_supported_features = CoverEntityFeature(self.features())

    @property
    def current_cover_position(self) -> int | None:
        """The position read, 0 closed to 100 open."""
        return self._position()

    async def async_open_cover(self, **kwargs: Any) -> None:
        """Send the open command, or move to 100 %."""
        await self._async_move("open", FULL)

    async def async_close_cover(self, **kwargs: Any) -> None:
        """Send the close command, or move to 0 %."""
        await self._async_move("close", 0)

    async def async_stop_cover(self, **kwargs: Any) -> None:
        """Send the stop command (a step relay: its pulse)."""
        await self._async_move("stop", None)

    @property
    def current_cover_tilt_position(self) -> int | None:
        """The tilt read, 0 closed to 100 open."""
        return self._position("tilt_position")

    async def async_set_cover_tilt_position(self, **kwargs: Any) -> None:
        """Write the tilt through its part's range."""
        await self._async_set_position(float(kwargs[ATTR_TILT_POSITION]), "tilt_position")

    async def async_set_cover_position(self, **kwargs: Any) -> None:
        """Write the position through the part's range."""
        await self._async_set_position(float(kwargs[ATTR_POSITION]))
