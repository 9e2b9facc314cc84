"""Every text the code or services.yaml refers to exists in strings.json, and icons.json is valid.

The code is read with `ast`, not regular expressions: translation keys passed as literals or as
module constants are found wherever they are used (flows, exceptions, issues, selectors, entity
descriptions, action registrations). A key built at run time cannot be checked here.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass
import json
from pathlib import Path
import re
from typing import Any

from homeassistant import const as ha_const
from homeassistant.const import Platform
from homeassistant.util.yaml import load_yaml_dict
import pytest
import voluptuous as vol

INTEGRATION = Path(__file__).resolve().parent.parent / "custom_components" / "plc_bridge"
STRINGS: dict[str, Any] = json.loads((INTEGRATION / "strings.json").read_text(encoding="utf-8"))
CODE = sorted(
    path for path in INTEGRATION.rglob("*.py") if path.relative_to(INTEGRATION).parts[0] != "plc"
)
SERVICES_YAML = INTEGRATION / "services.yaml"
SERVICES: dict[str, Any] = load_yaml_dict(SERVICES_YAML) if SERVICES_YAML.exists() else {}
PLATFORMS = {platform.value for platform in Platform}
ABORTS = {"async_abort", "async_update_and_abort", "async_update_reload_and_abort"}
FORMS = {"async_show_form", "async_show_menu", "async_show_progress"}
IMPLICIT_ABORTS = {
    "_abort_if_unique_id_configured": "already_configured",
    "_abort_if_unique_id_mismatch": "unique_id_mismatch",
}
SERVICE_REGISTRATIONS = {"async_register": 1, "async_register_entity_service": 0}
SERVICE_REGISTRATIONS["async_register_platform_entity_service"] = 2


@dataclass(frozen=True, slots=True)
class Use:
    """One translation key the code uses: its kind, key, and the platform for entity keys."""

    kind: str  # error, abort, step, exceptions, issues, selector, entity, services, any
    key: str
    line: int
    platform: str | None = None


def constants() -> dict[str, str]:
    """Return the string constants of the integration's modules and homeassistant.const."""
    found = {name: value for name, value in vars(ha_const).items() if isinstance(value, str)}
    for path in CODE:
        for node in ast.parse(path.read_text(encoding="utf-8")).body:
            target = node.target if isinstance(node, ast.AnnAssign) else None
            if isinstance(node, ast.Assign) and len(node.targets) == 1:
                target = node.targets[0]
            value = getattr(node, "value", None)
            if (
                isinstance(target, ast.Name)
                and isinstance(value, ast.Constant)
                and isinstance(value.value, str)
            ):
                found[target.id] = value.value
    return found


CONSTANTS = constants()


def text(node: ast.AST | None) -> str | None:
    """Return the string a node stands for, when it is a literal or a known constant."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return node.value
    if isinstance(node, ast.Name | ast.Attribute):
        return CONSTANTS.get(node.id if isinstance(node, ast.Name) else node.attr)
    return None


def callee(node: ast.Call) -> str:
    """Return the called function's last name part."""
    func = node.func
    return func.id if isinstance(func, ast.Name) else getattr(func, "attr", "")


def description_platform(name: str, module: str) -> str | None:
    """Return the platform of an EntityDescription class name, or of the module it is in."""
    words = re.sub(r"(?<!^)(?=[A-Z])", "_", name.removesuffix("EntityDescription")).lower()
    if words in PLATFORMS:
        return words
    return module if module in PLATFORMS else None


class Scanner(ast.NodeVisitor):
    """Collect the translation keys one module uses."""

    def __init__(self, module: str) -> None:
        """Start empty for a module (its stem names its platform, if it is one)."""
        self.module = module
        self.uses: list[Use] = []
        self._function = ""
        self._descriptions: dict[str, str | None] = {}  # description subclasses -> platform

    def add(self, kind: str, node: ast.AST | None, line: int, platform: str | None = None) -> None:
        """Record a key when it can be known without running the code."""
        if (key := text(node)) is not None:
            self.uses.append(Use(kind, key, line, platform))

    def visit_FunctionDef(self, node: ast.FunctionDef | ast.AsyncFunctionDef) -> None:
        """Remember the function, so dicts returned by error helpers count as form errors."""
        outer, self._function = self._function, node.name
        self.generic_visit(node)
        self._function = outer

    visit_AsyncFunctionDef = visit_FunctionDef

    def visit_ClassDef(self, node: ast.ClassDef) -> None:
        """Note the module's own EntityDescription subclasses and their platform."""
        for base in (ast.unparse(b).rsplit(".", 1)[-1] for b in node.bases):
            if base in self._descriptions:
                self._descriptions[node.name] = self._descriptions[base]
            elif base.endswith("EntityDescription"):
                self._descriptions[node.name] = description_platform(base, self.module)
        self.generic_visit(node)

    def visit_Call(self, node: ast.Call) -> None:
        """Keys passed to flows, exceptions, issues, selectors, descriptions, registrations."""
        name, kw = callee(node), {k.arg: k.value for k in node.keywords if k.arg}
        if name in ABORTS:
            self.add("abort", kw.get("reason"), node.lineno)
        if name in IMPLICIT_ABORTS:
            default = ast.Constant(IMPLICIT_ABORTS[name])
            self.add("abort", kw.get("reason", default), node.lineno)
        if name in FORMS:
            self.add("step", kw.get("step_id"), node.lineno)
        position = SERVICE_REGISTRATIONS.get(name, len(node.args))
        if len(node.args) > position and (
            name != "async_register" or "services" in ast.unparse(node.func)
        ):
            self.add("services", node.args[position], node.lineno)
        if "translation_key" in kw:
            self.add(self._kind(name, kw), kw["translation_key"], node.lineno, self._platform(name))
        self.generic_visit(node)

    def _kind(self, name: str, kw: dict[str, ast.expr]) -> str:
        """Return the strings.json section a translation_key keyword points into."""
        if name in ("async_create_issue", "create_issue"):
            return "issues"
        if name.endswith(("Selector", "SelectorConfig")):
            return "selector"
        if name.endswith("EntityDescription") or name in self._descriptions:
            return "entity"
        if "translation_domain" in kw or name.endswith(("Error", "Failed", "NotReady")):
            return "exceptions"
        return "any"

    def _platform(self, name: str) -> str | None:
        """Return the platform of an entity description call."""
        if name in self._descriptions:
            return self._descriptions[name]
        return description_platform(name, self.module)

    def visit_Assign(self, node: ast.Assign) -> None:
        """errors[field] = "key", and _attr_translation_key = "key"."""
        for target in node.targets:
            if isinstance(target, ast.Subscript) and ast.unparse(target.value).endswith("errors"):
                self.add("error", node.value, node.lineno)
            if ast.unparse(target).endswith("_attr_translation_key"):
                self.add("entity", node.value, node.lineno, description_platform("", self.module))
        self.generic_visit(node)

    def visit_Return(self, node: ast.Return) -> None:
        """The form errors a helper named *error* returns as a dict literal."""
        if isinstance(node.value, ast.Dict) and "error" in self._function.lower():
            for value in node.value.values:
                self.add("error", value, node.lineno)
        self.generic_visit(node)

    def visit_Dict(self, node: ast.Dict) -> None:
        """{"base": "key"} anywhere is a form error."""
        for key, value in zip(node.keys, node.values, strict=True):
            if text(key) == "base":
                self.add("error", value, node.lineno)
        self.generic_visit(node)


def flow_sections(part: str) -> dict[str, Any]:
    """Return one part (error, abort, step) of every flow: config, options, subentries, repairs."""
    owners = [STRINGS.get("config", {}), STRINGS.get("options", {})]
    owners += list(STRINGS.get("config_subentries", {}).values())
    owners += [
        issue["fix_flow"] for issue in STRINGS.get("issues", {}).values() if "fix_flow" in issue
    ]
    return {key: value for owner in owners for key, value in owner.get(part, {}).items()}


def known(use: Use) -> bool:
    """True when strings.json has a translation for the key."""
    entity = STRINGS.get("entity", {})
    if use.kind in ("error", "abort", "step"):
        return use.key in flow_sections(use.kind)
    if use.kind == "entity" and use.platform is not None:
        return use.key in entity.get(use.platform, {})
    if use.kind == "entity":
        return any(use.key in keys for keys in entity.values())
    if use.kind == "any":
        sections = ("exceptions", "issues", "selector")
        return any(use.key in STRINGS.get(s, {}) for s in sections) or known(
            Use("entity", use.key, 0)
        )
    if use.kind == "services":
        return use.key in STRINGS.get("services", {}) and use.key in SERVICES
    return use.key in STRINGS.get(use.kind, {})


@pytest.mark.parametrize("path", CODE, ids=lambda p: p.name)
def test_code_keys_are_translated(path: Path) -> None:
    """Every translation key a module uses exists in strings.json."""
    scanner = Scanner(path.stem)
    scanner.visit(ast.parse(path.read_text(encoding="utf-8")))
    missing = [f"{path.name}:{u.line} {u.kind} {u.key!r}" for u in scanner.uses if not known(u)]
    assert not missing


def test_english_is_strings() -> None:
    """translations/en.json is strings.json: a custom integration ships no build step."""
    english = json.loads((INTEGRATION / "translations" / "en.json").read_text(encoding="utf-8"))
    assert english == STRINGS
    assert "[%key:" not in json.dumps(STRINGS), "custom integrations cannot resolve [%key:...%]"


def leaves(value: Any, path: str = "") -> list[tuple[str, Any]]:
    """Return (path, value) of every leaf of a JSON tree."""
    if isinstance(value, dict):
        return [leaf for key, item in value.items() for leaf in leaves(item, f"{path}.{key}")]
    return [(path, value)]


def test_strings_are_text() -> None:
    """Every translation is a non-empty string without stray whitespace."""
    bad = [p for p, v in leaves(STRINGS) if not isinstance(v, str) or not v or v != v.strip()]
    assert not bad


def service_fields(service: dict[str, Any] | None) -> tuple[dict[str, Any], dict[str, Any]]:
    """Return (fields, sections) of a services.yaml entry; a section has its own fields."""
    fields: dict[str, Any] = {}
    sections: dict[str, Any] = {}
    for name, field in ((service or {}).get("fields") or {}).items():
        if isinstance(field, dict) and "fields" in field:
            sections[name] = field
            fields |= field["fields"]
        else:
            fields[name] = field
    return fields, sections


@pytest.mark.parametrize("service", sorted(SERVICES))
def test_action_is_translated(service: str) -> None:
    """An action and each of its fields has a name and a description; each section a name."""
    strings = STRINGS.get("services", {}).get(service, {})
    assert strings.get("name")
    assert strings.get("description")
    fields, sections = service_fields(SERVICES[service])
    for field in fields:
        field_strings = strings.get("fields", {}).get(field, {})
        assert field_strings.get("name"), field
        assert field_strings.get("description"), field
    for section in sections:
        assert strings.get("sections", {}).get(section, {}).get("name"), section


def test_translated_actions_exist() -> None:
    """strings.json translates no action that services.yaml does not describe."""
    assert set(STRINGS.get("services", {})) <= set(SERVICES)


def icon(value: Any) -> str:
    """Accept a Material Design icon name."""
    if not isinstance(value, str) or not re.fullmatch(r"mdi:[a-z0-9-]+", value):
        raise vol.Invalid(f"{value!r} is not an mdi: icon")
    return value


SLUG = vol.Match(r"^[a-z0-9_]+$")
STATE_ICONS = vol.Schema({str: icon})
ENTITY_ICON = vol.Schema(
    {
        vol.Optional("default"): icon,
        vol.Optional("state"): STATE_ICONS,
        vol.Optional("range"): vol.Schema({vol.Coerce(float): icon}),
        vol.Optional("state_attributes"): vol.Schema(
            {SLUG: {vol.Optional("default"): icon, vol.Optional("state"): STATE_ICONS}}
        ),
    }
)
ICONS_SCHEMA = vol.Schema(
    {
        vol.Optional("entity"): vol.Schema({vol.In(PLATFORMS): {SLUG: ENTITY_ICON}}),
        vol.Optional("services"): vol.Schema(
            {SLUG: {vol.Required("service"): icon, vol.Optional("sections"): {SLUG: icon}}}
        ),
    }
)


def test_icons() -> None:
    """icons.json follows the current schema, and every action has an icon (as hassfest asks)."""
    path = INTEGRATION / "icons.json"
    if not path.exists():
        assert not SERVICES, "actions need icons in icons.json"
        return
    icons = ICONS_SCHEMA(json.loads(path.read_text(encoding="utf-8")))
    assert set(icons.get("services", {})) == set(SERVICES)


def test_docs_name_every_action_as_admin_only() -> None:
    """README and quality_scale.yaml name every action of services.yaml, and say who may call."""
    readme = (INTEGRATION.parent.parent / "README.md").read_text(encoding="utf-8")
    scale = (INTEGRATION / "quality_scale.yaml").read_text(encoding="utf-8")
    for action in SERVICES:
        assert f"plc_bridge.{action}" in readme, action
        assert action in scale, action
        assert STRINGS["services"][action]["description"].endswith("Administrators only.")
    assert "for administrators only" in readme
    assert "admin-only" in scale
