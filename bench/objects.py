"""Objects per point entity: what each entity of a machine keeps, RSS per point, full collections.

`python -m bench.objects [--points 1000 10] [--trace] [--against DIR] [--json]` runs
bench/test_objects.py in Home Assistant's test harness once per size (a fresh process each, so
RSS is that size's): one
S7-200 SMART simulator on loopback, an entry whose machines hold a mix of kinds (plain and
scaled sensors, an enum sensor, a binary sensor, a switch, a number, a select, a switch of a
state and a command), set up, unloaded and set up again as after a restart, then polled.

From each point entity it walks `gc.get_referents`, stopping at what every entity shares (Home
Assistant, the entry and its stored points, the coordinator and its last values, the platform,
the loop, modules, classes, code and module-level functions), and counts the distinct objects of
all point entities together: an object reached from half the entities or more counts as shared
and is left out; one shared by a few (a device, a conversion equal for many points) counts once.
It prints the objects and bytes per point entity, the types that hold most, the RSS per point
(after the restart, against before the first setup) and the longest of a few full `gc.collect()`
runs; what the test harness alone keeps (its parsed copy of each file Home Assistant writes, its
captured log records) is left out. Then the objects by who keeps them, ours or Home Assistant's,
with the entity's State and the coordinator's listener entries, which the entity does not reach.
`--trace`: what stays allocated per point, by the module that allocated it (RSS and collections
then cost more).
`--against DIR`: the same first for other code (bench/against.py), so before and after come
from one command.
"""

from __future__ import annotations

import argparse
import asyncio
from collections import Counter
from collections.abc import Iterable
from functools import cached_property
import gc
import json
import os
from pathlib import Path
import shlex
import subprocess
import sys
import time
import tracemalloc
from types import BuiltinFunctionType, CodeType, FunctionType, ModuleType
from typing import Any

from homeassistant.config_entries import ConfigEntry, ConfigSubentryDataWithId
from homeassistant.core import EventBus, HomeAssistant, ServiceRegistry, StateMachine
from homeassistant.helpers.device_registry import DeviceRegistry
from homeassistant.helpers.entity import Entity
from homeassistant.helpers.entity_platform import EntityPlatform, async_get_platforms
from homeassistant.helpers.entity_registry import EntityRegistry
from homeassistant.helpers.update_coordinator import DataUpdateCoordinator

from bench.against import tree_with
from custom_components.plc_bridge.const import DOMAIN
from tests.entries import PointData, device, point

ROOT = Path(__file__).resolve().parent.parent
MACHINES = 10
"""Machines (device subentries) the points are spread over."""
KINDS = (
    "sensor",
    "scaled sensor",
    "enum sensor",
    "binary sensor",
    "switch",
    "number",
    "select",
    "state and command switch",
)
SHARED_SHARE = 0.5
"""An object reached from this share of the point entities or more is shared by all."""


def _kind_points(kind: int, index: int) -> list[PointData]:
    """The points of the index-th entity, of the kind-th of KINDS, at addresses of its own."""
    word, bits = f"VW{2 * index}", f"V{10000 + index // 4}.{2 * (index % 4)}"
    name, key = f"Point {index}", f"p{index}"
    if kind == 0:
        return [point(key, name, "sensor", word, "signed")]
    if kind == 1:
        return [
            point(
                key,
                name,
                "sensor",
                word,
                "signed",
                scale=0.1,
                unit_of_measurement="bar",
                device_class="pressure",
                state_class="measurement",
            )
        ]
    if kind == 2:
        return [point(key, name, "sensor", word, "signed", value_map="0=Off;1=Auto;2=Manual")]
    if kind == 3:
        return [point(key, name, "binary_sensor", bits, "signed", device_class="door")]
    if kind == 4:
        return [point(key, name, "switch", bits, "signed")]
    if kind == 5:
        return [point(key, name, "number", word, "signed", scale=0.5, min=0.0, max=100.0)]
    if kind == 6:
        return [point(key, name, "select", word, "signed", value_map="0=Off;1=Auto;2=Manual")]
    state = f"V{10000 + index // 4}.{2 * (index % 4) + 1}"
    return [
        point(f"{key}s", name, "switch", state, "signed", role="state", read_only=True),
        point(f"{key}c", name, "switch", bits, "signed", role="command"),
    ]


def machines(count: int) -> list[ConfigSubentryDataWithId]:
    """Machines holding `count` entities, the kinds in turn, as read back from storage.

    Through JSON as after a restart: no text is shared between points by the source's literals.
    """
    per = max(1, count // MACHINES)
    stored = [
        device(
            [p for index in range(m, min(m + per, count)) for p in _kind_points(index % 8, index)],
            subentry_id=f"machine{m // per}",
            title=f"Machine {m // per}",
        )
        for m in range(0, count, per)
    ]
    return [ConfigSubentryDataWithId(**item) for item in json.loads(json.dumps(stored))]


def shared_functions() -> set[int]:
    """The ids of every module's globals and every function a module or class holds."""
    found: set[int] = set()
    for module in list(sys.modules.values()):
        if not isinstance(module, ModuleType):
            continue
        found.add(id(vars(module)))
        for value in list(vars(module).values()):
            if isinstance(value, FunctionType):
                found.add(id(value))
            elif isinstance(value, type):
                for member in list(vars(value).values()):
                    function = member
                    if isinstance(member, classmethod | staticmethod):
                        function = member.__func__
                    elif isinstance(member, property):
                        function = member.fget
                    if isinstance(function, FunctionType):
                        found.add(id(function))
    return found


STOP_TYPES: tuple[type, ...] = (
    type,
    ModuleType,
    CodeType,
    BuiltinFunctionType,
    HomeAssistant,
    EventBus,
    StateMachine,
    ServiceRegistry,
    EntityRegistry,
    DeviceRegistry,
    ConfigEntry,
    DataUpdateCoordinator,
    EntityPlatform,
    asyncio.AbstractEventLoop,
)
"""What every entity refers to and none owns: the walk stops there."""


def reachable(root: object, stop: set[int]) -> dict[int, object]:
    """Every object reachable from `root` without passing what all entities share."""
    seen: dict[int, object] = {}
    todo = [root]
    while todo:
        item = todo.pop()
        key = id(item)
        if key in seen or key in stop or isinstance(item, STOP_TYPES):
            continue
        seen[key] = item
        todo.extend(gc.get_referents(item))
    return seen


def near(roots: Iterable[object], depth: int) -> set[int]:
    """The ids of the roots and of what they refer to, `depth` references deep at most.

    Entities and what the walk stops at anyway are passed over.
    """
    found: set[int] = set()
    level = list(roots)
    for _ in range(depth):
        level = [
            item
            for item in level
            if id(item) not in found and not isinstance(item, (Entity, *STOP_TYPES))
        ]
        found.update(id(item) for item in level)
        level = [ref for item in level for ref in gc.get_referents(item)]
    return found


HOME_ASSISTANT_SETS = frozenset(
    {
        "hass",
        "platform",
        "platform_data",
        "registry_entry",
        "device_entry",
        "entity_id",
        "parallel_updates",
        "coordinator",
        "_on_remove",
        "_unsub_device_updates",
        "_state_info",
        "_platform_state",
        "_cached_friendly_name",
        "_device_class_name",
        "_object_id_device_class_name",
        "_name_translation_key",
        "_verified_state_writable",
        "internal_integration_suggested_object_id",
    }
)
"""Attributes Home Assistant sets on every entity itself (its cached properties aside)."""


def ours(entity: object) -> list[object]:
    """The values of the attributes our code sets on an entity (Home Assistant's left out)."""
    cached = {
        name
        for cls in type(entity).__mro__
        if cls.__module__.startswith("homeassistant.")
        for name, member in vars(cls).items()
        if isinstance(member, cached_property)
    }
    return [
        value
        for name, value in vars(entity).items()
        if name not in HOME_ASSISTANT_SETS
        and name not in cached
        and not name.startswith("_sensor_option_")
    ]


def stop_set(hass: HomeAssistant, shared: Iterable[object] = ()) -> set[int]:
    """The ids the walks stop at: functions, what `hass.data` holds near its top, `shared`."""
    stop = shared_functions() | near(hass.data.values(), depth=3)
    for root in shared:
        stop |= reachable(root, stop).keys()
    return stop


OURS = "ours"
HOME_ASSISTANT = "Home Assistant"
OWNERS: tuple[tuple[str, str], ...] = (
    ("the entity instance and its __dict__", OURS),
    ("what our code sets on the entity (description, parts, ...)", OURS),
    ("coordinator listener: remover partial in _on_remove", OURS),
    ("coordinator listener: (callback, context) in the coordinator", OURS),
    ("other removal callbacks of ours (outputs, supervision)", OURS),
    ("entity registry entry", HOME_ASSISTANT),
    ("platform's removal closure (remove_entity_cb)", HOME_ASSISTANT),
    ("entity registry updates listener", HOME_ASSISTANT),
    ("device registry updates listener", HOME_ASSISTANT),
    ("device entry", HOME_ASSISTANT),
    ("Home Assistant's attributes and cached properties on the entity", HOME_ASSISTANT),
    ("State in the state machine (attributes, Context)", HOME_ASSISTANT),
)
"""Who keeps what per entity, in the order objects reached from several are attributed."""


def _removal_owner(callback: object) -> int:
    """The index in OWNERS of one of an entity's `_on_remove` callbacks."""
    func = getattr(callback, "func", callback)
    name = getattr(func, "__qualname__", "")
    module = getattr(func, "__module__", "") or ""
    if "remove_listener_internal" in name:
        return 2
    if "remove_entity_cb" in name:
        return 6
    if name == "_remove_listener":
        return 7
    if "unsubscribe_device_updates" in name:
        return 8
    return 4 if module.startswith("custom_components.") else 10


def _owned_roots(
    entity: Entity, listeners: dict[int, list[object]], state: object
) -> list[tuple[int, object]]:
    """Each root an entity's objects are reached from, with the index of its owner in OWNERS."""
    own = {id(value) for value in ours(entity)}
    roots: list[tuple[int, object]] = []
    for name, value in vars(entity).items():
        if name == "_on_remove":  # the list is Home Assistant's, each callback its owner's
            roots += [(_removal_owner(item), item) for item in value or ()]
            roots.append((10, value))
        elif name == "registry_entry":
            roots.append((5, value))
        elif name == "_unsub_device_updates":
            roots.append((8, value))
        elif name == "device_entry":
            roots.append((9, value))
        else:
            roots.append((1 if id(value) in own else 10, value))
    roots += [(3, item) for item in listeners.get(id(entity), [])]
    if state is not None:
        roots.append((11, state))
    return roots


def count_owners(
    hass: HomeAssistant,
    entities: Iterable[Entity],
    coordinators: Iterable[DataUpdateCoordinator[Any]],
    shared: Iterable[object] = (),
) -> list[dict[str, Any]]:
    """Objects and bytes per entity by who keeps them (OWNERS), also what the entity cannot reach.

    The walk of count_objects plus the entity's State in the state machine and the entries
    of the coordinator's listener dict (a tuple of the callback and its context each, reached
    only from the coordinator); objects reached from half the entities or more are left out.
    """
    entities = list(entities)
    stop = stop_set(hass, shared) | {id(entity) for entity in entities}
    listeners: dict[int, list[object]] = {}
    for coordinator in coordinators:
        for entry in coordinator._listeners.values():
            owner = getattr(entry[0], "__self__", None)
            if owner is not None:
                listeners.setdefault(id(owner), []).extend([entry, entry[0]])
    walks = []
    reached: Counter[int] = Counter()
    for entity in entities:
        state = hass.states.get(entity.entity_id) if entity.entity_id else None
        found: dict[int, tuple[int, object]] = {
            id(entity): (0, entity),
            id(vars(entity)): (0, vars(entity)),
        }
        for owner, root in _owned_roots(entity, listeners, state):
            todo = [root]
            while todo:
                item = todo.pop()
                key = id(item)
                if key in found or key in stop or isinstance(item, STOP_TYPES):
                    continue
                found[key] = (owner, item)
                todo.extend(gc.get_referents(item))
        reached.update(found.keys())
        walks.append(found)
    limit = max(2, SHARED_SHARE * len(entities))
    objects = [0] * len(OWNERS)
    sizes = [0] * len(OWNERS)
    seen: set[int] = set()
    for found in walks:
        for key, (owner, item) in found.items():
            if reached[key] < limit and key not in seen:
                seen.add(key)
                objects[owner] += 1
                sizes[owner] += sys.getsizeof(item)
    count = max(1, len(entities))
    return [
        {
            "owner": name,
            "kept_by": kept_by,
            "objects_per_entity": round(objects[index] / count, 2),
            "bytes_per_entity": round(sizes[index] / count),
        }
        for index, (name, kept_by) in enumerate(OWNERS)
    ]


def count_objects(
    hass: HomeAssistant, entities: Iterable[object], shared: Iterable[object] = ()
) -> dict[str, Any]:
    """Objects and bytes per entity, shared ones left out, and the types that hold the most.

    What `hass.data` holds near its top (the event trackers' callbacks, the registries) is
    shared: the walk stops there, and at all `shared` reaches (the entry's stored points, the
    coordinator's last values: kept whatever the entities keep). `ours_per_entity` counts the
    entity, its attributes' dict and what the attributes our code sets reach; the rest is what
    Home Assistant keeps per entity (its registry entry, listeners and caches).
    """
    entities = list(entities)
    stop = stop_set(hass, shared)
    reached: Counter[int] = Counter()
    objects: dict[int, object] = {}
    own: set[int] = set()
    for entity in entities:
        found = reachable(entity, stop)
        reached.update(found.keys())
        objects |= found
        instance = {id(entity), id(vars(entity))}
        own |= instance
        for value in ours(entity):
            own |= reachable(value, stop | instance).keys()
    limit = max(2, SHARED_SHARE * len(entities))
    kept = [key for key, times in reached.items() if times < limit]
    types = Counter(type(objects[key]).__qualname__ for key in kept)
    count = max(1, len(entities))
    return {
        "entities": len(entities),
        "objects_per_entity": round(len(kept) / count, 1),
        "ours_per_entity": round(sum(1 for key in kept if key in own) / count, 1),
        "bytes_per_entity": round(sum(sys.getsizeof(objects[key]) for key in kept) / count),
        "ours_bytes_per_entity": round(
            sum(sys.getsizeof(objects[key]) for key in kept if key in own) / count
        ),
        "shared_left_out": sum(1 for times in reached.values() if times >= limit),
        "types_per_entity": {
            name: round(number / count, 2) for name, number in types.most_common(12)
        },
    }


def _module_of(traceback: tracemalloc.Traceback) -> str:
    """The module of the innermost frame in Home Assistant or ours; else the innermost's file."""
    for frame in reversed(traceback):
        for top in ("homeassistant/", "custom_components/"):
            if top in frame.filename:
                return top + frame.filename.rpartition(top)[2]
    return Path(traceback[-1].filename).name if len(traceback) else "?"


def allocated_by(
    before: tracemalloc.Snapshot, after: tracemalloc.Snapshot, points: int
) -> list[dict[str, Any]]:
    """KiB and blocks per point still allocated, by the module of Home Assistant or ours that
    allocated them (the innermost such frame), the largest first."""
    kib: Counter[str] = Counter()
    blocks: Counter[str] = Counter()
    for stat in after.compare_to(before, "traceback"):
        module = _module_of(stat.traceback)
        kib[module] += stat.size_diff
        blocks[module] += stat.count_diff
    return [
        {
            "module": module,
            "kib_per_point": round(size / 1024 / points, 2),
            "blocks_per_point": round(blocks[module] / points, 1),
        }
        for module, size in kib.most_common(14)
    ]


def point_entities(hass: HomeAssistant) -> list[Entity]:
    """The entities of the machines' points (those of a machine's device, not the PLC's)."""
    return [
        entity
        for platform in async_get_platforms(hass, DOMAIN)
        for entity in platform.entities.values()
        if getattr(entity, "_machine", None) is not None
    ]


def tracked_types() -> Counter[str]:
    """The objects the garbage collector tracks, by type (module and name)."""
    return Counter(
        f"{type(item).__module__}.{type(item).__qualname__}" for item in gc.get_objects()
    )


def rss_kib() -> float:
    """The resident set size of this process, in KiB."""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return float(line.split()[1])
    return float("nan")


def longest_full_collection(times: int = 7) -> tuple[float, float]:
    """The longest of a few full collections, in ms: by the clock, and in this thread's CPU time.

    The CPU time leaves out what other processes on a shared machine take meanwhile. Timed by
    the system's clocks: the test harness freezes Python's.
    """
    wall = cpu = 0.0
    for _ in range(times):
        started = time.clock_gettime(time.CLOCK_MONOTONIC)
        used = time.clock_gettime(time.CLOCK_THREAD_CPUTIME_ID)
        gc.collect()
        cpu = max(cpu, time.clock_gettime(time.CLOCK_THREAD_CPUTIME_ID) - used)
        wall = max(wall, time.clock_gettime(time.CLOCK_MONOTONIC) - started)
    return wall * 1000, cpu * 1000


def run(points: int, trace: bool = False, tree: Path = ROOT) -> dict[str, Any] | str:
    """Run the Home Assistant part for one size in `tree`; its figures, or its output's tail."""
    env = os.environ | {"BENCH_POINTS": str(points), "BENCH_TRACE": "1" if trace else ""}
    command = [sys.executable, "-m", "pytest", "bench/test_objects.py", "-q", "-s"]
    # pytest's log capture keeps every record a test logs: a real Home Assistant keeps none.
    command += ["-p", "no:cacheprovider", "-p", "no:logging"]
    done = subprocess.run(command, cwd=tree, env=env, capture_output=True, text=True, check=False)
    for line in done.stdout.splitlines():
        if line.startswith("BENCH "):
            return dict(json.loads(line.removeprefix("BENCH ")))
    return done.stdout[-3000:] + done.stderr[-3000:]


def text(result: dict[str, Any]) -> list[str]:
    """Return one size's figures as lines."""
    types = ", ".join(f"{name} {n:g}" for name, n in result["types_per_entity"].items())
    lines = [
        f"{result['entities']} point entities ({', '.join(KINDS)} in turn):",
        f"  objects per point entity: {result['objects_per_entity']:g}"
        f" ({result['bytes_per_entity']} bytes), {result['ours_per_entity']:g} of them"
        f" ({result['ours_bytes_per_entity']} bytes) the entity and what our code sets on it;"
        f" {result['shared_left_out']} objects shared by half the entities or more left out",
        f"  most per entity: {types}",
        f"  RSS per point entity after a restart: {result['rss_kib_per_point']:.1f} KiB",
        f"  longest full gc.collect(): {result['gc_full_max_ms']:.1f} ms"
        f" ({result.get('gc_full_max_cpu_ms', float('nan')):.1f} ms of CPU;"
        f" {result['gc_objects']} objects tracked)",
    ]
    owners = result.get("owners", [])
    if owners:
        lines.append("  objects per point entity by who keeps them (the State included):")
    for kept_by in (OURS, HOME_ASSISTANT):
        rows = [row for row in owners if row["kept_by"] == kept_by]
        total = sum(row["objects_per_entity"] for row in rows)
        size = sum(row["bytes_per_entity"] for row in rows)
        if rows:
            lines.append(f"    {kept_by}: {total:.1f} objects ({size} bytes)")
        lines += [
            f"      {row['objects_per_entity']:5.2f} ({row['bytes_per_entity']:4d} bytes)"
            f" {row['owner']}"
            for row in rows
        ]
    if "tracked_per_point" in result:
        lines.append(
            f"  objects the GC tracks per point, the coordinator's and the entry's included:"
            f" {result['tracked_per_point']:g}; most:"
        )
        lines += [
            f"    {count:6.2f} {name}" for name, count in result["tracked_types_per_point"].items()
        ]
    if result.get("allocated_by"):
        lines.append("  tracemalloc, still allocated per point after the restart, by module:")
    lines += [
        f"    {row['kib_per_point']:6.2f} KiB {row['blocks_per_point']:6.1f} blocks {row['module']}"
        for row in result.get("allocated_by", [])
    ]
    return lines


def main() -> int:
    """Parse the command line, run each size, print."""
    parser = argparse.ArgumentParser(prog="python -m bench.objects", description=__doc__)
    parser.add_argument("--points", type=int, nargs="+", default=[1000, 10])
    parser.add_argument("--json", action="store_true")
    parser.add_argument(
        "--trace", action="store_true", help="tracemalloc by module (RSS and GC then include it)"
    )
    parser.add_argument(
        "--against", type=Path, help="a folder of other code to measure first (bench/against.py)"
    )
    args = parser.parse_args()
    trees = [("this tree", ROOT)]
    if args.against is not None:
        trees.insert(0, (f"against {args.against}", tree_with(args.against)))
    results = []
    for label, tree in trees:
        for points in args.points:
            result = run(points, args.trace, tree)
            if isinstance(result, str):
                print(f"the objects benchmark failed ({label}):\n{result}")
                return 1
            results.append((label, result))
    if args.json:
        print(json.dumps([result | {"code": label} for label, result in results]))
        return 0
    print(f"$ {shlex.join(['python', '-m', 'bench.objects', *sys.argv[1:]])}")
    for label, result in results:
        print(f"# {label}:")
        print("\n".join(text(result)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
