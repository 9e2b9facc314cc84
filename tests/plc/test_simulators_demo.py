"""The demo mode of `python -m simulators`: values that move, once a second, until stopped."""

from __future__ import annotations

import asyncio
from pathlib import Path
from typing import Any

import pytest

from simulators.__main__ import SIMULATORS, _animate, _count, keep_certificate
from simulators.plcnext import PlcnextSimulator
from simulators.plcnext.demo import MACHINES as PLCNEXT_MACHINES
from simulators.s7_smart import S7SmartSimulator
from simulators.tecomat import TecomatSimulator
from simulators.tecomat.program import MACHINES as TECOMAT_MACHINES


class Recorder:
    """A simulator stand-in that records the times it was animated."""

    def __init__(self) -> None:
        self.calls: list[float] = []

    def animate(self, elapsed: float) -> None:
        self.calls.append(elapsed)


async def test_animate_until_stopped() -> None:
    """Animated at once and then about every second; a simulator without animate is left."""
    recorder, stop = Recorder(), asyncio.Event()
    running: list[tuple[Any, Any]] = [(SIMULATORS[0], recorder), (SIMULATORS[1], object())]
    task = asyncio.create_task(_animate(running, stop))
    await asyncio.sleep(0.05)
    assert len(recorder.calls) == 1
    assert recorder.calls[0] < 0.05
    stop.set()
    await asyncio.wait_for(task, 1)


def test_s7_smart_process() -> None:
    """The tank temperature drifts in 0.1 steps, the counter counts; nothing else moves."""
    sim = S7SmartSimulator()
    sim.set("VD104", 5.0, "float")
    sim.animate(0.0)
    assert sim.get("VD100", "float") == 21.5
    assert sim.get("VW10") == 0
    sim.animate(225.0)  # a quarter of the 15-minute wave
    assert sim.get("VD100", "float") == 23.0
    assert sim.get("VW10") == 225
    assert sim.get("VD104", "float") == 5.0


def test_certificate_kept_across_starts(tmp_path: Path) -> None:
    """The demo's pinned entries keep working: a restarted simulator shows the same certificate."""
    first, second = S7SmartSimulator(), S7SmartSimulator()
    keep_certificate(first, tmp_path / "certs", "s7_smart")
    keep_certificate(second, tmp_path / "certs", "s7_smart")
    assert first.fingerprint is not None
    assert first.fingerprint == second.fingerprint
    assert (tmp_path / "certs" / "s7_smart.key").stat().st_mode & 0o077 == 0
    fresh = S7SmartSimulator()
    fresh.new_certificate()
    assert fresh.fingerprint != first.fingerprint


def test_control_counters() -> None:
    """The bench's control pipe tells requests and connections (None where none are kept)."""
    sim = S7SmartSimulator()
    sim.requests = 7
    sim.peers = {("127.0.0.1", 50000), ("127.0.0.1", 50001)}
    assert _count(sim, "requests") == 7
    assert _count(sim, "connections") == 2
    assert _count(object(), "connections") is None


@pytest.mark.parametrize(
    ("simulator", "machines"),
    [(TecomatSimulator, TECOMAT_MACHINES), (PlcnextSimulator, PLCNEXT_MACHINES)],
)
def test_demo_machines_run(simulator: Any, machines: dict[str, str]) -> None:
    """The boiler's water drifts and raises Overheat above a set point only; the pump's
    contactor follows its command; the shutter's commands reach its limit switches."""
    sim = simulator()
    sim.animate(450.0)
    assert (sim.get(machines["water"]), sim.get(machines["alarms"])) == (500, 0)  # no set point
    sim.set(machines["alarms"], 8)
    sim.set(machines["target"], 225)
    sim.set(machines["run"], True)
    sim.set(machines["open"], True)
    sim.animate(450.0)
    assert sim.get(machines["alarms"]) == 9  # bit 0 raised, the others kept
    assert sim.get(machines["running"]) is True
    assert (sim.get(machines["opened"]), sim.get(machines["closed"])) == (True, False)
    sim.set(machines["target"], 600)
    sim.animate(450.0)
    assert sim.get(machines["alarms"]) == 8
