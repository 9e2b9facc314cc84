"""Repository metadata checks that hassfest and the HACS action would make, run offline.

manifest.json, hacs.json, quality_scale.yaml, the brand icon, and that every JSON file parses.
The translation, action and icon checks are in test_meta_translations.py.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
import struct
from typing import Any

from awesomeversion import AwesomeVersion, AwesomeVersionStrategy
import homeassistant.components
from homeassistant.const import __version__ as HA_VERSION
from homeassistant.util.yaml import load_yaml_dict
from packaging.requirements import Requirement
import pytest
import voluptuous as vol

ROOT = Path(__file__).resolve().parent.parent
INTEGRATION = ROOT / "custom_components" / "plc_bridge"
SKIP_DIRS = {".git", ".venv", "config", "node_modules", "htmlcov", "__pycache__"}
SKIP_DIRS |= {".mypy_cache", ".ruff_cache", ".pytest_cache"}
SKIP_DIRS |= {".demo-check", ".wt"}  # the demo check's throwaway config; helpers' worktrees

# Home Assistant's own lists (script/hassfest, not shipped in the homeassistant package).
IOT_CLASSES = ["assumed_state", "calculated", "cloud_polling", "cloud_push", "local_polling"]
IOT_CLASSES += ["local_push"]
INTEGRATION_TYPES = ["device", "entity", "hardware", "helper", "hub", "service", "system"]
TIERS = ["bronze", "silver", "gold", "platinum"]
HACS_KEYS = ["name", "content_in_root", "zip_release", "filename", "hide_default_branch"]
HACS_KEYS += ["country", "homeassistant", "render_readme", "hacs", "persistent_directory"]

# The Integration Quality Scale, rule by tier, as script/hassfest/quality_scale.py lists it.
RULES: dict[str, list[str]] = {
    "bronze": [
        "action-setup",
        "appropriate-polling",
        "brands",
        "common-modules",
        "config-flow",
        "config-flow-test-coverage",
        "dependency-transparency",
        "docs-actions",
        "docs-conditions",
        "docs-high-level-description",
        "docs-installation-instructions",
        "docs-removal-instructions",
        "docs-triggers",
        "entity-event-setup",
        "entity-unique-id",
        "has-entity-name",
        "runtime-data",
        "test-before-configure",
        "test-before-setup",
        "unique-config-entry",
    ],
    "silver": [
        "action-exceptions",
        "config-entry-unloading",
        "docs-configuration-parameters",
        "docs-installation-parameters",
        "entity-unavailable",
        "integration-owner",
        "log-when-unavailable",
        "parallel-updates",
        "reauthentication-flow",
        "test-coverage",
    ],
    "gold": [
        "devices",
        "diagnostics",
        "discovery",
        "discovery-update-info",
        "docs-data-update",
        "docs-examples",
        "docs-known-limitations",
        "docs-supported-devices",
        "docs-supported-functions",
        "docs-troubleshooting",
        "docs-use-cases",
        "dynamic-devices",
        "entity-category",
        "entity-device-class",
        "entity-disabled-by-default",
        "entity-translations",
        "exception-translations",
        "icon-translations",
        "reconfiguration-flow",
        "repair-issues",
        "stale-devices",
    ],
    "platinum": ["async-dependency", "inject-websession", "strict-typing"],
}


def repo_files(name_filter: str) -> list[Path]:
    """Return the repository's files whose names end with `name_filter` (no venv, no caches)."""
    found = []
    for folder, dirs, files in os.walk(ROOT):
        dirs[:] = sorted(d for d in dirs if d not in SKIP_DIRS and not d.startswith(".venv"))
        found += [Path(folder, f) for f in sorted(files) if f.endswith(name_filter)]
    return found


def load_json(path: Path) -> Any:
    """Return a JSON file's content."""
    return json.loads(path.read_text(encoding="utf-8"))


def version(value: str) -> str:
    """Accept the version formats hassfest accepts."""
    strategies = [
        AwesomeVersionStrategy.CALVER,
        AwesomeVersionStrategy.SEMVER,
        AwesomeVersionStrategy.SIMPLEVER,
        AwesomeVersionStrategy.BUILDVER,
        AwesomeVersionStrategy.PEP440,
    ]
    if AwesomeVersion(value).strategy not in strategies:
        raise vol.Invalid(f"{value!r} is not a valid version")
    return value


SHARED_WITH_CORE = {"lxml"}
"""Requirements Home Assistant's own integrations pin too (lxml: scrape). Ours takes a lower
bound that every supported release's pin meets: an exact pin of another version would make Home
Assistant reinstall the package for one integration, then for the other, at every start."""


def pinned(value: str) -> str:
    """Accept a requirement pinned to one version, or bounded below where core pins it too."""
    requirement = Requirement(value)
    operators = {spec.operator for spec in requirement.specifier}
    if operators == {"=="} or (requirement.name in SHARED_WITH_CORE and operators == {">="}):
        return value
    raise vol.Invalid(f"{value!r} is not pinned with == (nor a lower bound of {SHARED_WITH_CORE})")


def mac_pattern(value: str) -> str:
    """Accept a DHCP matcher's MAC pattern as hassfest does: upper case, with a wildcard."""
    if value != value.upper() or "*" not in value:
        raise vol.Invalid(f"{value!r} is not an upper-case pattern with a wildcard")
    return value


def host_pattern(value: str) -> str:
    """Accept a DHCP matcher's host name pattern as hassfest does: lower case."""
    if value != value.lower():
        raise vol.Invalid(f"{value!r} is not lower case")
    return value


def codeowner(value: str) -> str:
    """Accept a GitHub user or team."""
    if not value.startswith("@"):
        raise vol.Invalid(f"{value!r} is not a GitHub @handle")
    return value


MANIFEST_SCHEMA = vol.Schema(
    {
        vol.Required("domain"): INTEGRATION.name,
        vol.Required("name"): str,
        vol.Required("codeowners"): [codeowner],
        vol.Optional("config_flow"): bool,
        vol.Optional("dependencies"): [str],
        vol.Optional("dhcp"): [
            vol.Schema(
                {
                    vol.Optional("macaddress"): vol.All(str, mac_pattern),
                    vol.Optional("hostname"): vol.All(str, host_pattern),
                    vol.Optional("registered_devices"): bool,
                }
            )
        ],
        vol.Optional("after_dependencies"): [str],
        vol.Required("documentation"): vol.Url(),
        vol.Optional("import_executor"): bool,
        vol.Required("integration_type"): vol.In(INTEGRATION_TYPES),
        vol.Required("iot_class"): vol.In(IOT_CLASSES),
        vol.Required("issue_tracker"): vol.Url(),
        vol.Optional("loggers"): [str],
        vol.Optional("quality_scale"): vol.In([*TIERS, "internal"]),
        vol.Optional("requirements"): [pinned],
        vol.Optional("single_config_entry"): bool,
        vol.Required("version"): vol.All(str, version),
    }
)
STATUS_SCHEMA = vol.Any(
    "done",
    vol.Schema(
        {vol.Required("status"): "done", vol.Optional("comment"): vol.All(str, vol.Length(1))}
    ),
    vol.Schema(
        {
            vol.Required("status"): vol.In(["todo", "exempt"]),
            vol.Required("comment"): vol.All(str, vol.Length(1)),
        }
    ),
)


@pytest.fixture(name="manifest")
def manifest_fixture() -> dict[str, Any]:
    """The integration's manifest."""
    data: dict[str, Any] = load_json(INTEGRATION / "manifest.json")
    return data


@pytest.mark.parametrize("path", repo_files(".json"), ids=lambda p: str(p.relative_to(ROOT)))
def test_json_parses(path: Path) -> None:
    """Every JSON file in the repository parses."""
    load_json(path)


def test_one_manifest() -> None:
    """The integration's manifest is the only manifest.json (HACS finds the integration by it)."""
    assert repo_files("manifest.json") == [INTEGRATION / "manifest.json"]


def test_manifest_schema(manifest: dict[str, Any]) -> None:
    """The manifest has the keys and values hassfest accepts for a custom integration."""
    MANIFEST_SCHEMA(manifest)
    assert "python-snap7==3.3.0" in manifest["requirements"]


def test_manifest_key_order(manifest: dict[str, Any]) -> None:
    """domain and name first, then the other keys in alphabetical order, as hassfest sorts them."""
    keys = list(manifest)
    assert keys == ["domain", "name", *sorted(keys[2:])]


def test_requirements_match_tests(manifest: dict[str, Any]) -> None:
    """The tests run against the requirement versions Home Assistant will install."""
    test_lines = (ROOT / "requirements_test.txt").read_text(encoding="utf-8").splitlines()
    pins = {
        Requirement(line).name: Requirement(line)
        for line in (text.split("#")[0].strip() for text in test_lines)
        if line
    }
    for text in manifest["requirements"]:
        wanted = Requirement(text)
        (tested,) = pins[wanted.name].specifier
        assert tested.operator == "=="
        assert wanted.specifier.contains(tested.version), (text, str(tested))


def test_shared_requirements_fit_core(manifest: dict[str, Any]) -> None:
    """Every pin this release's own integrations make of a shared requirement meets ours."""
    components = Path(homeassistant.components.__file__).parent
    ours = {
        Requirement(text).name: Requirement(text)
        for text in manifest["requirements"]
        if Requirement(text).name in SHARED_WITH_CORE
    }
    checked = 0
    for path in components.glob("*/manifest.json"):
        for text in json.loads(path.read_text(encoding="utf-8")).get("requirements", []):
            theirs = Requirement(text)
            if theirs.name in ours and theirs.specifier:
                (spec,) = theirs.specifier
                assert ours[theirs.name].specifier.contains(spec.version), (path.parent.name, text)
                checked += 1
    assert checked, "no core integration pins lxml any more: pin it exactly again"


def test_config_flow(manifest: dict[str, Any]) -> None:
    """A manifest that declares a config flow ships one."""
    assert manifest["config_flow"] is True
    if not (INTEGRATION / "config_flow.py").exists():
        pytest.skip("config_flow.py is not written yet")


def test_hacs_json(manifest: dict[str, Any]) -> None:
    """hacs.json has only keys HACS accepts and the Home Assistant minimum we test against."""
    hacs = load_json(ROOT / "hacs.json")
    assert set(hacs) <= set(HACS_KEYS), set(hacs) - set(HACS_KEYS)
    assert hacs["name"] == manifest["name"]
    assert hacs["homeassistant"] == "2026.2.3"  # what requirements_oldest.txt tests
    assert AwesomeVersion(HA_VERSION) >= AwesomeVersion(hacs["homeassistant"])
    assert hacs.get("content_in_root", False) is False
    assert not hacs.get("zip_release", False), "zip_release needs a release asset workflow"


@pytest.fixture(name="quality_rules")
def quality_rules_fixture() -> dict[str, Any]:
    """The rules of quality_scale.yaml."""
    rules: dict[str, Any] = load_yaml_dict(INTEGRATION / "quality_scale.yaml")["rules"]
    return rules


def test_quality_scale_lists_every_rule(quality_rules: dict[str, Any]) -> None:
    """Every rule of the scale is there, and no unknown one."""
    known = [rule for tier in TIERS for rule in RULES[tier]]
    assert sorted(quality_rules) == sorted(known)


@pytest.mark.parametrize("rule", [rule for tier in TIERS for rule in RULES[tier]])
def test_quality_scale_status(quality_rules: dict[str, Any], rule: str) -> None:
    """A rule is done, todo or exempt; todo and exempt say why in a comment."""
    STATUS_SCHEMA(quality_rules.get(rule))


def test_quality_scale_tier_is_met(manifest: dict[str, Any], quality_rules: dict[str, Any]) -> None:
    """The manifest claims no tier whose rules (and all lower tiers') are not all done or exempt."""
    claimed = manifest.get("quality_scale")
    if claimed not in TIERS:
        return
    open_rules = [
        rule
        for tier in TIERS[: TIERS.index(claimed) + 1]
        for rule in RULES[tier]
        if (
            quality_rules[rule]
            if isinstance(quality_rules[rule], str)
            else quality_rules[rule]["status"]
        )
        == "todo"
    ]
    assert not open_rules, f"{claimed} claimed, but these rules are todo: {open_rules}"


@pytest.mark.parametrize(("name", "size"), [("icon.png", 256), ("icon@2x.png", 512)])
def test_brand_icon(name: str, size: int) -> None:
    """The brand icon is a square PNG of the size the brands repository asks for."""
    data = (INTEGRATION / "brand" / name).read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert data[12:16] == b"IHDR"
    assert struct.unpack(">II", data[16:24]) == (size, size)
