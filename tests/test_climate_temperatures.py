"""Climate temperatures on the `native_*` properties where Home Assistant has them (2026.11 on).

Home Assistant 2026.11 reads `native_current_temperature`, `native_target_temperature` and
`native_temperature_unit`, and reports (in the log, which fails any test: tests/conftest.py) an
entity that still gives the old names, removed in 2027.11. The harnesses here (2026.2.3 and
2026.10.4) read only the old names; the entity gives the old names there, and only there.
"""

from __future__ import annotations

from collections.abc import Iterator
import importlib
from types import ModuleType

from homeassistant.components.climate import ClimateEntity
import pytest

from custom_components.plc_bridge import climate

OLD_NAMES = {"current_temperature", "target_temperature", "temperature_unit"}


@pytest.fixture
def newer_climate(monkeypatch: pytest.MonkeyPatch) -> Iterator[ModuleType]:
    """The climate platform as loaded under a Home Assistant whose climate has native names."""
    monkeypatch.setattr(
        ClimateEntity, "native_current_temperature", property(lambda self: None), raising=False
    )
    yield importlib.reload(climate)
    monkeypatch.undo()
    importlib.reload(climate)


def test_native_names_only_where_home_assistant_has_them(newer_climate: ModuleType) -> None:
    """Under a climate with `native_*` the entity defines none of the names it deprecates."""
    entity = newer_climate.PlcClimate
    assert not OLD_NAMES & set(vars(entity))
    assert {"native_current_temperature", "native_target_temperature"} <= set(vars(entity))


def test_old_names_kept_for_this_home_assistant() -> None:
    """Without `native_*` in Home Assistant's climate, the old names carry the same values."""
    has_native = hasattr(ClimateEntity, "native_current_temperature")
    assert has_native == climate.NATIVE_TEMPERATURES
    defined = set(vars(climate.PlcClimate))
    assert {"native_current_temperature", "native_target_temperature"} <= defined
    assert ({"current_temperature", "target_temperature"} <= defined) != has_native
