"""Objects per point entity: what each entity of a machine keeps, RSS per point, full collections.

`python -m bench.objects [--points 1000 10] [--json]` runs bench/test_objects.py in Home
Assistant's test harness once per size (a fresh process each, so RSS is that size's): one
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
runs.
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
from types import BuiltinFunctionType, CodeType, FunctionType, ModuleType
from typing import Any

from homeassistant.config_entries import ConfigEntry, ConfigSubentryDataWithId
from homeassistant.core import EventBus, HomeAssistant, ServiceRegistry, StateMachine
from homeassistant.helpers.device_registry import DeviceRegistry
from homeassistant.helpers.entity import Entity
from homeassistant.helpers.entity_platform import EntityPlatform, async_get_platforms
from homeassistant.helpers.entity_registry import EntityRegistry
from homeassistant.helpers.update_coordinator import DataUpdateCoordinator

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
    stop = shared_functions() | near(hass.data.values(), depth=3)
    for root in shared:
        stop |= reachable(root, stop).keys()
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


def point_entities(hass: HomeAssistant) -> list[Entity]:
    """The entities of the machines' points (those of a machine's device, not the PLC's)."""
    return [
        entity
        for platform in async_get_platforms(hass, DOMAIN)
        for entity in platform.entities.values()
        if getattr(entity, "_machine", None) is not None
    ]


def rss_kib() -> float:
    """The resident set size of this process, in KiB."""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return float(line.split()[1])
    return float("nan")


def longest_full_collection(times: int = 5) -> float:
    """The longest of a few full collections, in ms.

    Timed by the system's monotonic clock: the test harness freezes Python's clocks.
    """
    longest = 0.0
    for _ in range(times):
        started = time.clock_gettime(time.CLOCK_MONOTONIC)
        gc.collect()
        longest = max(longest, time.clock_gettime(time.CLOCK_MONOTONIC) - started)
    return longest * 1000


def run(points: int) -> dict[str, Any] | str:
    """Run the Home Assistant part for one size; its figures, or the tail of its output."""
    env = os.environ | {"BENCH_POINTS": str(points)}
    command = [sys.executable, "-m", "pytest", "bench/test_objects.py", "-q", "-s"]
    command += ["-p", "no:cacheprovider"]
    done = subprocess.run(command, cwd=ROOT, env=env, capture_output=True, text=True, check=False)
    for line in done.stdout.splitlines():
        if line.startswith("BENCH "):
            return dict(json.loads(line.removeprefix("BENCH ")))
    return done.stdout[-3000:] + done.stderr[-3000:]


def text(result: dict[str, Any]) -> list[str]:
    """Return one size's figures as lines."""
    types = ", ".join(f"{name} {n:g}" for name, n in result["types_per_entity"].items())
    return [
        f"{result['entities']} point entities ({', '.join(KINDS)} in turn):",
        f"  objects per point entity: {result['objects_per_entity']:g}"
        f" ({result['bytes_per_entity']} bytes), {result['ours_per_entity']:g} of them"
        f" ({result['ours_bytes_per_entity']} bytes) the entity and what our code sets on it;"
        f" {result['shared_left_out']} objects shared by half the entities or more left out",
        f"  most per entity: {types}",
        f"  RSS per point entity after a restart: {result['rss_kib_per_point']:.1f} KiB",
        f"  longest full gc.collect(): {result['gc_full_max_ms']:.1f} ms"
        f" ({result['gc_objects']} objects tracked)",
    ]


def main() -> int:
    """Parse the command line, run each size, print."""
    parser = argparse.ArgumentParser(prog="python -m bench.objects", description=__doc__)
    parser.add_argument("--points", type=int, nargs="+", default=[1000, 10])
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    results = []
    for points in args.points:
        result = run(points)
        if isinstance(result, str):
            print(f"the objects benchmark failed:\n{result}")
            return 1
        results.append(result)
    if args.json:
        print(json.dumps(results))
        return 0
    print(f"$ {shlex.join(['python', '-m', 'bench.objects', *sys.argv[1:]])}")
    for result in results:
        print("\n".join(text(result)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
