"""No Home Assistant release we run on reports a deprecated use by PLC Bridge.

Home Assistant reports some deprecations when a platform module is imported (an entity class
that provides a member it renames: helpers/deprecation.py), before any test's log is captured:
so each platform module is imported in a fresh interpreter of each Home Assistant at hand
(this harness's, and the demo's newer release where it is installed), and the demo check's own
filter reads what it logs. The reports made while a test runs fail that test (conftest.py).
"""

from __future__ import annotations

from pathlib import Path
import subprocess
import sys

import pytest

from custom_components.plc_bridge.model.kinds import PLATFORMS

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts"))
from demo_check import deprecated_use  # noqa: E402

DEMO = ROOT / ".venv-demo" / "bin" / "python"
HERE = Path(sys.executable)
PYTHONS = [HERE, *([DEMO] if DEMO.exists() and HERE != DEMO else [])]
IMPORT_ALL = (
    "import importlib, logging\n"
    "logging.basicConfig(level=logging.WARNING)\n"
    "for name in {names!r}:\n"
    "    importlib.import_module('custom_components.plc_bridge.' + name)\n"
)


def test_the_filter_reads_both_wordings() -> None:
    """The demo check's filter catches both ways Home Assistant words a deprecated use."""
    assert deprecated_use(
        "WARNING:x:custom_components.plc_bridge.climate::PlcClimate provides the deprecated "
        "current_temperature, this will stop working in Home Assistant 2027.11"
    )
    assert deprecated_use(
        "Detected that custom integration 'plc_bridge' calls hass.foo, which is deprecated"
    )
    assert not deprecated_use("Detected that custom integration 'other' uses a deprecated call")
    assert not deprecated_use("custom_components.plc_bridge: Boiler house is back")


@pytest.mark.parametrize("python", PYTHONS, ids=lambda path: path.parent.parent.name)
def test_platform_modules_use_nothing_deprecated(python: Path) -> None:
    """Importing every platform module logs no deprecated use of PLC Bridge."""
    names = [str(platform) for platform in PLATFORMS]
    run = subprocess.run(
        [str(python), "-c", IMPORT_ALL.format(names=names)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert run.returncode == 0, run.stderr[-2000:]
    reported = [line for line in run.stderr.splitlines() if deprecated_use(line)]
    assert not reported, "\n".join(reported)
