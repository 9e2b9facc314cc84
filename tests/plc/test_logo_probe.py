"""Discovery: a LOGO! confirms its server TSAP; an S7 CPU does not, nor does a LOGO! a rack/slot."""

from __future__ import annotations

from typing import Any

from custom_components.plc_bridge.plc.vendors import probe_of
from simulators.logo import LogoSimulator
from simulators.s7 import S7Simulator
from tests.loopback import running


async def probe(vendor: str, sim: Any) -> dict[str, Any] | None:
    """Run a vendor's probe against a simulator (the probe touches no HTTP session)."""
    found = probe_of(vendor)
    assert found is not None
    return await found(sim.host, sim.port, None, 2.0)  # type: ignore[arg-type]


async def test_probe_finds_a_logo() -> None:
    """Each generation is offered with its TSAPs; the S7 probe does not take a LOGO! for a CPU."""
    for generation, remote in (("0ba8", "20.00"), ("0ba7", "10.00")):
        async with running(LogoSimulator(generation)) as sim:
            found = await probe("logo", sim)
            assert found is not None
            assert (found["generation"], found["remote_tsap"]) == (generation, remote)
            assert await probe("s7", sim) is None
            assert sim.requests == 0  # no S7 job, not even a setup


async def test_an_s7_cpu_is_no_logo() -> None:
    """A CPU served by rack and slot refuses the LOGO! server TSAPs."""
    async with running(S7Simulator()) as sim:
        assert await probe("logo", sim) is None
        assert await probe("s7", sim) == {"rack": 0, "slot": 1}
