"""The PLCs the output tests run on (S7-200 SMART and TecoApi simulators) and write faults.

`plc` (import `plc_fixture`) is a started simulator with the addresses of a cover's parts and
a pulse button; `faults` (import `faults_fixture`) wraps the entry's client write: each queued
fault hits one write, every write is recorded (with whether it was sent as urgent), and after
each one the memory is checked for open and close requested at once.
"""

from __future__ import annotations

from collections.abc import AsyncGenerator, Callable
from dataclasses import dataclass, field
from datetime import timedelta
from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.core import HomeAssistant
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry, async_fire_time_changed

from custom_components.plc_bridge.plc import PlcConnectionError, PlcTimeoutError
from custom_components.plc_bridge.plc.http import URGENT
from simulators.s7_smart import S7SmartSimulator
from simulators.tecomat import TecomatSimulator

from .ha_fixtures import CLOCK, PointData, make_entry, point, serving
from .tecomat_ha_fixtures import make_tecomat_entry

ROLES = ("open", "close", "stop", "open_limit", "closed_limit", "position", "status", "button")


@dataclass
class Plc:
    """A started simulator, where the test's parts live, and how its entities are named."""

    vendor: str
    sim: Any
    prefix: str
    addresses: dict[str, str]
    bit: str  # the data type of a bit
    word: str  # the data type of a whole number
    make: Callable[[HomeAssistant, Any, list[PointData]], MockConfigEntry]

    def get(self, role: str) -> Any:
        """Return what the PLC holds at a role's address (bits as bool)."""
        value = self.sim.get(self.addresses[role])
        return bool(value) if role not in ("position", "status") else value

    def set(self, role: str, value: Any) -> None:
        """Set what the PLC holds at a role's address (the program or the machine did)."""
        self.sim.set(self.addresses[role], value)

    def part(
        self, role: str, name: str = "Shutter", platform: str = "cover", **extra: Any
    ) -> PointData:
        """Return a part of the test cover (or another entity) at the role's address."""
        kind = self.word if role in ("position", "status") else self.bit
        read_only = role in ("open_limit", "closed_limit", "status")
        data = {"role": role, "read_only": read_only} | extra
        return point(f"{name}_{role}".lower(), name, platform, self.addresses[role], kind, **data)

    async def set_up(self, hass: HomeAssistant, points: list[PointData]) -> MockConfigEntry:
        """Add and set up the PLC's entry with these points."""
        entry = self.make(hass, self.sim, points)
        assert await hass.config_entries.async_setup(entry.entry_id)
        await hass.async_block_till_done()
        return entry

    def entity(self, platform: str, name: str = "shutter") -> str:
        """Return the entity id of a test entity."""
        return f"{platform}.{self.prefix}_{name}"


S7_SMART = {
    "open": "Q0.4",
    "close": "Q0.5",
    "stop": "Q0.6",
    "open_limit": "I0.1",
    "closed_limit": "I0.2",
    "position": "VW40",
    "status": "VW44",
    "button": "Q0.2",
}
TECOMAT = {
    "open": "Shutter.open",
    "close": "Shutter.close",
    "stop": "Pump.start",
    "open_limit": "Shutter.opened",
    "closed_limit": "Shutter.closed",
    "position": "plcData.varInt",
    "status": "plcData.varUint",
    "button": "Pump.run",
}


@pytest.fixture(name="plc", params=["s7_smart", "tecomat"])
async def plc_fixture(
    request: pytest.FixtureRequest, hass: HomeAssistant, freezer: FrozenDateTimeFactory
) -> AsyncGenerator[Plc]:
    """A started simulator of each vendor the output tests run on (time frozen until unload)."""
    if request.param == "s7_smart":
        sim = S7SmartSimulator()
        sim.clock = CLOCK
        async with serving(hass, sim):
            yield Plc("s7_smart", sim, "s7_200_smart", S7_SMART, "signed", "signed", make_entry)
        return
    tecomat = TecomatSimulator(bench=0)
    tecomat.set("plcData.varInt", 0)
    tecomat.set("plcData.varUint", 0)
    async with serving(hass, tecomat):
        yield Plc("tecomat", tecomat, "fx2_cp2080", TECOMAT, "BOOL", "INT", make_tecomat_entry)


FAULTS = {
    "lost_answer": "the write lands, its answer is lost (a timeout)",
    "dropped": "the connection drops before the write lands",
}


@dataclass
class Faults:
    """Faults injected into the entry's client writes, and what every write carried."""

    plc: Plc
    queue: list[str] = field(default_factory=list)
    writes: list[tuple[dict[str, Any], bool]] = field(default_factory=list)
    both: list[int] = field(default_factory=list)  # writes after which open and close were on

    def wrap(self, client: Any, monkeypatch: pytest.MonkeyPatch) -> None:
        """Route the client's writes through the fault queue."""
        original = client.write

        async def write(values: Any) -> Any:
            self.writes.append(({p.address: v for p, v in values.items()}, URGENT.get()))
            fault = self.queue.pop(0) if self.queue else None
            if fault == "dropped":
                raise PlcConnectionError("the connection was reset")
            try:
                return await original(values)
            finally:
                if self.plc.get("open") and self.plc.get("close"):
                    self.both.append(len(self.writes))
                if fault == "lost_answer":
                    raise PlcTimeoutError("the PLC did not answer in time")

        monkeypatch.setattr(client, "write", write)

    def sent(self, role: str) -> list[Any]:
        """The values written to a role's address, in order."""
        address = self.plc.addresses[role]
        return [values[address] for values, _ in self.writes if address in values]


@pytest.fixture(name="faults")
def faults_fixture(plc: Plc) -> Faults:
    """The fault queue of the test PLC (wrap it once the entry is set up)."""
    return Faults(plc)


async def wait(hass: HomeAssistant, freezer: FrozenDateTimeFactory, seconds: float) -> None:
    """Let time pass and the timers and tasks due run."""
    freezer.tick(timedelta(seconds=seconds))
    async_fire_time_changed(hass)
    await hass.async_block_till_done(wait_background_tasks=True)
