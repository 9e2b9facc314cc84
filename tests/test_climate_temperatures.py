"""Climate and water heater temperatures on `native_*` where Home Assistant has them (2026.11 on).

Home Assistant 2026.11 reads `native_current_temperature`, `native_target_temperature` and
`native_temperature_unit`, and reports (in the log, which fails any test: tests/conftest.py) an
entity that still gives the old names, removed in 2027.11. The harnesses here (2026.2.3 and
2026.10.4) read only the old names; the entity gives the old names there, and only there.
"""

from __future__ import annotations

from pathlib import Path
import subprocess
import sys

from homeassistant.components.climate import ClimateEntity

from custom_components.plc_bridge import composite_entity
from custom_components.plc_bridge.climate import PlcClimate
from custom_components.plc_bridge.water_heater import PlcWaterHeater

OLD_NAMES = {"current_temperature", "target_temperature", "temperature_unit"}
NATIVE = {"native_current_temperature", "native_target_temperature"}
NEWER = (
    "from homeassistant.components.climate import ClimateEntity\n"
    "ClimateEntity.native_current_temperature = property(lambda self: None)\n"
    "from custom_components.plc_bridge import composite_entity as c\n"
    "assert c.NATIVE_TEMPERATURES\n"
    "print(sorted(vars(c.PlcTemperatureEntity)))\n"
)
"""Load the entity base under a Home Assistant whose climate has native names (a fresh
interpreter: the loaded modules stay as they are)."""


def test_native_names_only_where_home_assistant_has_them() -> None:
    """Under a climate with `native_*` the entities define none of the names it deprecates."""
    run = subprocess.run(
        [sys.executable, "-c", NEWER],
        cwd=Path(__file__).resolve().parent.parent,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert run.returncode == 0, run.stderr[-2000:]
    defined = set(eval(run.stdout.strip().splitlines()[-1]))
    assert not OLD_NAMES & defined
    assert defined >= NATIVE


def test_old_names_kept_for_this_home_assistant() -> None:
    """Without `native_*` in Home Assistant's climate, the old names carry the same values."""
    has_native = hasattr(ClimateEntity, "native_current_temperature")
    assert has_native == composite_entity.NATIVE_TEMPERATURES
    defined = set(vars(composite_entity.PlcTemperatureEntity))
    assert defined >= NATIVE
    assert ({"current_temperature", "target_temperature"} <= defined) != has_native
    for entity in (PlcClimate, PlcWaterHeater):
        assert issubclass(entity, composite_entity.PlcTemperatureEntity)
