"""SoftPLC fixtures for the protocol tests: a WEB.TLM simulator and clients of it."""

from __future__ import annotations

from collections.abc import AsyncGenerator
from typing import Any

import pytest

from custom_components.plc_bridge.plc import ConnectionConfig, TlsMode
from custom_components.plc_bridge.plc.vendors.softplc import SoftplcClient, exchange
from simulators.softplc import SoftplcSimulator
from tests.loopback import ConfigFactory, config_factory, connected, running


@pytest.fixture
async def softplc_sim() -> AsyncGenerator[SoftplcSimulator]:
    """A SoftPLC simulator on 127.0.0.1: plain HTTP, addresses echoed, no PUT authentication."""
    async with running(SoftplcSimulator()) as sim:
        yield sim


@pytest.fixture
async def softplc_tls_sim() -> AsyncGenerator[SoftplcSimulator]:
    """A SoftPLC simulator over HTTPS that takes PUTs only with a client certificate."""
    async with running(SoftplcSimulator(tls=True, put_auth=True)) as sim:
        yield sim


def softplc_config(sim: SoftplcSimulator, **changes: Any) -> ConnectionConfig:
    """Return the settings of a client of the simulator (pinned when it speaks TLS)."""
    tls = TlsMode.PIN if sim.tls else TlsMode.NONE
    return config_factory(sim, tls=tls, timeout=5.0)(**changes)


@pytest.fixture
def softplc_settings() -> ConfigFactory:
    """Return `softplc_config`, for tests that start simulators of their own."""
    return softplc_config


@pytest.fixture
async def softplc_client(softplc_sim: SoftplcSimulator) -> AsyncGenerator[SoftplcClient]:
    """A client connected to the plain simulator (its own HTTP session), closed afterwards."""
    async with connected(SoftplcClient(softplc_config(softplc_sim))) as client:
        yield client


VARIANTS: dict[str, dict[str, Any]] = {
    "defaults": {},
    "normalised": {"normalize": True},
    "normalised-numbered": {"normalize": True, "fixed": "numbered"},
    "bad-item-alone": {"bad_item": "item"},
    "bad-item-child": {"bad_item": "item", "item_error": "child"},
    "error-html": {"error_style": "html"},
    "error-text": {"error_style": "text"},
    "error-404": {"error_status": 404},
    "past-end-error": {"past_end": "error"},
    "foreign-codes": {"foreign_codes": True},
    "foreign-codes-alone": {"foreign_codes": True, "bad_item": "item"},
    "tags-exact": {"tag_case": "exact"},
    "tags-as-sent": {"tag_reply": "sent"},
    "tags-as-address": {"tag_reply": "address"},
    "tags-as-normalised-address": {"tag_reply": "address", "normalize": True},
    "short-is-file": {"short": "file"},
    "short-is-file-normalised": {"short": "file", "normalize": True},
    "reply-forms-refused": {"reply_forms": "refused"},
    "words-hex": {"words": "hex"},
    "words-signed": {"words": "signed"},
    "extra-attributes": {"extra": True},
    "extra-attributes-alone": {"extra": True, "bad_item": "item"},
    "reversed": {"order": "reversed"},
    "reversed-normalised": {"order": "reversed", "normalize": True},
}
"""Every reading of simulators/softplc/READINGS.md as simulator switches, one at a time and in
the pairs where one switch only shows with another. Tests take `softplc_reading`."""


@pytest.fixture(params=list(VARIANTS), ids=list(VARIANTS))
async def softplc_reading(
    request: pytest.FixtureRequest,
) -> AsyncGenerator[tuple[SoftplcSimulator, SoftplcClient]]:
    """A simulator answering one variant of VARIANTS, and a connected client of it."""
    switches = dict(VARIANTS[request.param])
    sim = SoftplcSimulator(normalize=switches.pop("normalize", False), bench=0)
    for switch, value in switches.items():
        assert hasattr(sim, switch), switch
        setattr(sim, switch, value)
    async with running(sim), connected(SoftplcClient(softplc_config(sim))) as client:
        yield sim, client


@pytest.fixture
def busy_waits(monkeypatch: pytest.MonkeyPatch) -> list[float]:
    """Record the waits a busy PLC makes the client sleep, and sleep none of them."""
    waits: list[float] = []

    async def record(seconds: float) -> None:
        waits.append(seconds)

    monkeypatch.setattr(exchange, "sleep", record)
    return waits


BUSY_READINGS: dict[str, dict[str, Any]] = {
    "no-retry-after": {"busy_retry": "none"},
    "retry-after-seconds": {"busy_retry": "seconds", "busy_wait": 2},
    "retry-after-date": {"busy_retry": "date", "busy_wait": 2},
}
"""Row 14 of simulators/softplc/READINGS.md: the Retry-After a busy answer carries, or none."""


def expected_wait(sim: SoftplcSimulator) -> tuple[float, float]:
    """Return the least and most seconds the client may wait after one busy answer of `sim`."""
    if sim.busy_retry == "none":
        return exchange.BACKOFF, exchange.BACKOFF
    if sim.busy_retry == "date":  # an HTTP-date counts whole seconds
        return sim.busy_wait - 1.5, float(sim.busy_wait)
    return float(sim.busy_wait), float(sim.busy_wait)


@pytest.fixture(params=list(BUSY_READINGS), ids=list(BUSY_READINGS))
async def softplc_busy(
    request: pytest.FixtureRequest,
) -> AsyncGenerator[tuple[SoftplcSimulator, SoftplcClient]]:
    """A simulator whose busy answers follow one reading of BUSY_READINGS, and a client of it."""
    sim = SoftplcSimulator(bench=0)
    for switch, value in BUSY_READINGS[request.param].items():
        assert hasattr(sim, switch), switch
        setattr(sim, switch, value)
    async with running(sim), connected(SoftplcClient(softplc_config(sim))) as client:
        yield sim, client


REAL_READINGS = ["g7", "comma", "exponent", "long", "short", "grouped"]
"""Row 15 of simulators/softplc/READINGS.md: how the PLC prints a float (switch `reals`)."""


@pytest.fixture(params=REAL_READINGS, ids=REAL_READINGS)
async def softplc_reals(
    request: pytest.FixtureRequest,
) -> AsyncGenerator[tuple[SoftplcSimulator, SoftplcClient]]:
    """A simulator printing floats as one reading of REAL_READINGS, and a client of it."""
    sim = SoftplcSimulator(bench=0)
    sim.reals = request.param
    async with running(sim), connected(SoftplcClient(softplc_config(sim))) as client:
        yield sim, client
