"""The package's layout holds: imports run one way, no circle, only what HA looks up on top.

Every module is read with `ast`; an import counts wherever it stands (at the top, under
`if TYPE_CHECKING:`, inside a function). The layers, from the bottom: `plc` (the protocol layer),
`const`, `model`, `runtime`, `coordinator`, the entity bases, and what Home Assistant looks up
(platforms, `__init__`, `config_flow`, `diagnostics`, `services`, `repairs`). A module may import
its own layer and those below it. `flows` stand aside: they may import the model, the runtime's
connection, `const`, `plc` and each other, and only `config_flow` (or `__init__`) imports them.
"""

from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

from homeassistant.const import Platform
import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "custom_components" / "plc_bridge"
NAME = "custom_components.plc_bridge"
ENTITY_BASES = frozenset({"entity", "composite_entity", "link"})
FACE = frozenset({"__init__", "config_flow", "diagnostics", "services", "repairs", "logbook"})
PLATFORMS = frozenset(platform.value for platform in Platform)
TOP = FACE | ENTITY_BASES | {"const", "coordinator"}
"""The modules allowed at the package top, besides the entity platforms."""
RANKS = {"plc": 0, "const": 1, "model": 2, "runtime": 3, "coordinator": 4, "bases": 5, "face": 6}
FLOWS_MAY_IMPORT = frozenset({"plc", "const", "model", "flows", "runtime.connection"})
FLOWS_IMPORTED_BY = frozenset({"config_flow", "__init__"})


def modules() -> dict[str, Path]:
    """Return every module of the package by dotted name below it (`model.points`)."""
    found: dict[str, Path] = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(PACKAGE).with_suffix("").parts
        if parts[-1] == "__init__" and len(parts) > 1:
            parts = parts[:-1]
        found[".".join(parts)] = path
    return found


MODULES = modules()


def imported(name: str, path: Path) -> Iterator[tuple[str, int]]:
    """Yield each module of ours the module imports (annotation and local imports too)."""
    package = name.split(".") if path.name == "__init__.py" and name != "__init__" else []
    package = package or name.split(".")[:-1]
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[: len(package) - (node.level - 1)]
                module = ".".join([*base, *([node.module] if node.module else [])])
            elif node.module == NAME or (node.module or "").startswith(f"{NAME}."):
                module = (node.module or "").removeprefix(NAME).lstrip(".")
            else:
                targets = [node.module or ""]
                yield from ((target, node.lineno) for target in targets if False)
                continue
            for alias in node.names:
                sub = f"{module}.{alias.name}" if module else alias.name
                yield (sub if sub in MODULES else module or "__init__"), node.lineno
            continue
        else:
            continue
        for target in targets:
            if target == NAME or target.startswith(f"{NAME}."):
                yield target.removeprefix(NAME).lstrip(".") or "__init__", node.lineno


def external(path: Path) -> Iterator[tuple[str, int]]:
    """Yield each absolute module the file imports from outside the package, with its line."""
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            yield from ((alias.name, node.lineno) for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and not node.level and node.module:
            yield node.module, node.lineno


def layer(name: str) -> str:
    """Return the layer a module belongs to."""
    first = name.split(".", maxsplit=1)[0]
    if first in ("plc", "model", "runtime", "flows"):
        return first
    if name in ENTITY_BASES:
        return "bases"
    if name in ("const", "coordinator"):
        return name
    return "face"


def graph() -> dict[str, set[str]]:
    """Return each module's imports of our other modules (package markers left out)."""
    edges: dict[str, set[str]] = {}
    for name, path in MODULES.items():
        edges[name] = {
            target
            for target, _ in imported(name, path)
            if target != name and target in MODULES and target not in ("model", "runtime", "flows")
        }
    return edges


def test_the_package_top_holds_only_what_home_assistant_looks_up() -> None:
    """Platforms, the integration's hooks and the entity bases; the rest lives in a package."""
    top = {name for name in MODULES if "." not in name} - {"plc", "model", "runtime", "flows"}
    assert top - TOP - PLATFORMS == set()
    assert {path.name for path in PACKAGE.iterdir() if path.is_dir()} <= {
        "plc",
        "model",
        "runtime",
        "flows",
        "translations",
        "brand",
        "__pycache__",
    }


@pytest.mark.parametrize("name", sorted(MODULES), ids=str)
def test_imports_run_one_way(name: str) -> None:
    """A module imports only its own layer and those below; flows stand aside."""
    source = layer(name)
    wrong = []
    for target, line in imported(name, MODULES[name]):
        if target not in MODULES or target in ("model", "runtime", "flows"):
            continue
        goes = layer(target)
        if source == "plc":
            allowed = goes == "plc"
        elif source == "flows":
            allowed = goes in FLOWS_MAY_IMPORT or target in FLOWS_MAY_IMPORT
        elif goes == "flows":
            allowed = name in FLOWS_IMPORTED_BY
        else:
            allowed = RANKS[goes] <= RANKS[source]
        if not allowed:
            wrong.append(f"line {line}: {name} ({source}) imports {target} ({goes})")
    assert wrong == []


def cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """Return the circles of the import graph, each as the modules along it."""
    state: dict[str, int] = {}
    stack: list[str] = []
    found: list[list[str]] = []

    def visit(name: str) -> None:
        """Depth-first walk; a module met again on the stack closes a circle."""
        state[name] = 1
        stack.append(name)
        for target in sorted(edges[name]):
            if state.get(target) == 1:
                found.append([*stack[stack.index(target) :], target])
            elif target not in state:
                visit(target)
        stack.pop()
        state[name] = 2

    for name in sorted(edges):
        if name not in state:
            visit(name)
    return found


def test_no_import_cycle() -> None:
    """No circle among the integration's modules, annotation imports included."""
    edges = {
        name: {target for target in targets if layer(target) != "plc"}
        for name, targets in graph().items()
        if layer(name) != "plc"
    }
    assert cycles(edges) == []


@pytest.mark.xfail(
    strict=True,
    reason="plc/vendors/softplc/writing.py names SoftplcClient in annotations (TYPE_CHECKING)",
)
def test_no_import_cycle_in_the_protocol_layer() -> None:
    """No circle inside plc/ either (one is left there: the layout change kept plc/ as it was)."""
    edges = {
        name: {target for target in targets if layer(target) == "plc"}
        for name, targets in graph().items()
        if layer(name) == "plc"
    }
    assert cycles(edges) == []


@pytest.mark.parametrize("name", sorted(n for n in MODULES if layer(n) == "plc"), ids=str)
def test_protocol_layer_imports_nothing_of_home_assistant_nor_of_ours(name: str) -> None:
    """plc/ could be published as its own library: no homeassistant, nothing outside plc/."""
    path = MODULES[name]
    home = [
        f"line {line}: {mod}"
        for mod, line in external(path)
        if mod.split(".")[0] == "homeassistant"
    ]
    ours = [
        f"line {line}: {target}" for target, line in imported(name, path) if layer(target) != "plc"
    ]
    assert home == []
    assert ours == []


def test_one_home_for_the_entry_types() -> None:
    """`PlcBridgeConfigEntry` and `PlcRuntimeData` are defined once, and imported from there."""
    homes = []
    for name, path in MODULES.items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in tree.body:
            defined = getattr(node, "name", None)
            if isinstance(defined, ast.Name):
                defined = defined.id
            if defined in ("PlcBridgeConfigEntry", "PlcRuntimeData"):
                homes.append((defined, name))
    assert sorted(homes) == [
        ("PlcBridgeConfigEntry", "coordinator"),
        ("PlcRuntimeData", "coordinator"),
    ]
