"""Plant benchmark: ten PLCs of 1,000 points in one Home Assistant, figures beside the targets.

`python -m bench.plant [--minutes N] [--plcs 10] [--points 1000] [--changing 1000] [--trace]
[--against DIR]`
runs bench/test_plant.py in Home Assistant's test harness (in this process's Python, real time):
S7-200 SMART simulators in a subprocess, every point a sensor in ten devices per PLC, the
vendor's pacing on unless `--pacing 0`. It prints the time until every entity is registered and
available, the event loop's lag (max, p99, stalls of 250 ms or more with the GC pauses and our
state writes inside them), how long each poll's state writes hold the loop, full collections,
and the RSS from the end of the start-up to N minutes later, and per point against before setup.
`--against DIR` runs the same first for other code (bench/against.py), then both side by side.
What the harness alone keeps (its parsed copy of each file Home Assistant writes) is dropped
before each measure, and loggers log warnings only, as Home Assistant's do by default.
"""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path
import shlex
import subprocess
import sys
from typing import Any

from bench.against import tree_with

ROOT = Path(__file__).resolve().parent.parent
TARGETS = {
    "registered": 5.0,  # s after start, every entity registered
    "hold": 50.0,  # ms a poll of 1,000 changing points holds the loop
    "stall": 250.0,  # ms: no stall this long caused by us
    "rss": 5.0,  # % RSS may move in steady polling
}


def run(args: argparse.Namespace, tree: Path = ROOT) -> dict[str, Any] | str:
    """Run the Home Assistant part in `tree`; its figures, or its output's tail when it failed."""
    env = os.environ | {
        "BENCH_PLCS": str(args.plcs),
        "BENCH_POINTS": str(args.points),
        "BENCH_MINUTES": str(args.minutes),
        "BENCH_CHANGING": str(args.changing),
        "BENCH_PERIOD": str(args.period),
        "BENCH_PACING": str(args.pacing),
        "BENCH_TRACE": "1" if args.trace else "",
        "BENCH_FAULT": str(args.faults),
    }
    command = [sys.executable, "-m", "pytest", "bench/test_plant.py", "-q", "-s"]
    command += ["-p", "no:cacheprovider"]
    done = subprocess.run(command, cwd=tree, env=env, capture_output=True, text=True, check=False)
    for line in done.stdout.splitlines():
        if line.startswith("BENCH "):
            return dict(json.loads(line.removeprefix("BENCH ")))
    return done.stdout[-3000:] + done.stderr[-3000:]


def text(result: dict[str, Any], command: str, load: tuple[float, ...]) -> str:
    """Return the figures as lines, each beside its target."""
    rss = result["rss_mib"]
    plcs = result["plcs"]
    first, last = rss[0][1], rss[-1][1]
    later = next((m for t, m in rss if t >= result["minutes"] * 20), first)
    faults = f"a PLC away every {result['fault_s']:g} s" if result["fault_s"] else "no faults"
    # A stall is ours when our state writes, garbage collection inside them aside, fill half of it.
    ours = [s for s in result["stalls"] if s["ours_ms"] - s["gc_ms"] >= s["lag_ms"] / 2]
    lines = [
        f"$ {command}",
        f"# load average before the run: {' '.join(f'{x:.2f}' for x in load)}"
        f" ({os.cpu_count()} CPUs, shared)",
        f"{result['plcs']} PLCs x {result['points']} points (S7-200 SMART simulators,"
        f" pacing {result['pacing_s']} s, {result['changing_per_plc']} values changing per PLC,"
        f" {faults}),"
        f" {result['minutes']} min of polling after the start-up",
        f"first start (entities registered anew) returned after"
        f" {result['first_setup_returned_s']} s; then as after a restart:",
        f"setup returned after {result['setup_returned_s']} s; every entity registered after"
        f" {result['all_registered_s']} s (target <= {TARGETS['registered']:g} s); all available"
        f" after {result['all_available_s']} s",
        f"event loop lag: max {result['lag_max_ms']} ms, p99 {result['lag_p99_ms']} ms;"
        f" {len(result['stalls'])} stalls >= {TARGETS['stall']:g} ms, {len(ours)} of them"
        f" mostly our state writes (target 0)",
    ]
    lines += [
        f"  stall {s['lag_ms']} ms at {s['at_s']} s: GC {s['gc_ms']} ms, our writes"
        f" {s['ours_ms']} ms (GC included) inside"
        for s in result["stalls"][:10]
    ]
    lines += [
        f"a poll's state writes hold the loop: max {result['hold_max_ms']} ms"
        f" ({result['hold_max_without_gc_ms']} ms without the GC inside), median"
        f" {result['hold_median_ms']} ms ({result['holds']} holds, {result['polls']} polls)"
        f" (target <= {TARGETS['hold']:g} ms); {result['state_changes']} state changes",
        f"full collections (GC generation 2): {result['gc_gen2']}, longest"
        f" {result['gc_gen2_max_ms']} ms ({result.get('gc_gen2_max_cpu_ms', '?')} ms of CPU)",
        f"RSS: {first} MiB after the start-up, {last} MiB after {rss[-1][0]} s"
        f" ({(last - first) / first * 100:+.1f} %; {(last - later) / later * 100:+.1f} % from a"
        f" third of the run on, target +/- {TARGETS['rss']:g} % in steady polling);"
        f" samples every 10 s: {' '.join(f'{m:g}' for _t, m in rss)}",
    ]
    if "gc_forced_cpu_ms" in result:
        forced = result["gc_forced_cpu_ms"]
        lines.append(
            f"full collections forced at the end: median {forced[len(forced) // 2]} ms of CPU"
            f" (min {forced[0]}, max {forced[-1]}); {result['gc_tracked']} objects tracked by"
            f" the GC, {tracked_per_point(result):.1f} per point"
        )
    if "rss_before_setup_mib" in result:
        per_point = (first - result["rss_before_setup_mib"]) * 1024 / (plcs * result["points"])
        lines.append(
            f"RSS per point: {per_point:.1f} KiB after the start-up (against"
            f" {result['rss_before_setup_mib']} MiB before the first setup)"
        )
    if result["growth"]:
        lines.append("tracemalloc, the largest growths from a third of the run to its end:")
    for row in result["growth"]:
        mark = "OURS " if row["ours"] else ""
        lines.append(f"  {mark}{row['where']}: {row['kib']:+} KiB, {row['count']:+} blocks")
    return "\n".join(lines)


def main() -> int:
    """Parse the command line, run, print."""
    parser = argparse.ArgumentParser(prog="python -m bench.plant", description=__doc__)
    parser.add_argument("--minutes", type=float, default=3.0, help="polling after start-up")
    parser.add_argument("--plcs", type=int, default=10)
    parser.add_argument("--points", type=int, default=1000, help="per PLC")
    parser.add_argument("--changing", type=int, default=1000, help="values changing per PLC")
    parser.add_argument("--period", type=float, default=5.0, help="s between value changes")
    parser.add_argument("--pacing", type=float, default=1.0, help="s between requests")
    parser.add_argument("--trace", action="store_true", help="tracemalloc: what grew, by line")
    parser.add_argument(
        "--faults", type=float, default=0.0, help="every N s the next PLC is away for N/2 s"
    )
    parser.add_argument("--json", action="store_true")
    parser.add_argument(
        "--against", type=Path, help="a folder of other code to run first (bench/against.py)"
    )
    args = parser.parse_args()
    trees = [("this tree", ROOT)]
    if args.against is not None:
        trees.insert(0, (f"against {args.against}", tree_with(args.against)))
    command = shlex.join(["python", "-m", "bench.plant", *sys.argv[1:]])
    results = []
    for label, tree in trees:
        load = os.getloadavg()
        result = run(args, tree)
        if isinstance(result, str):
            print(f"the plant benchmark failed ({label}):\n{result}")
            return 1
        results.append((label, result, load))
    if args.json:
        print(json.dumps([result | {"code": label} for label, result, _load in results]))
        return 0
    for label, result, load in results:
        print(f"# {label}:")
        print(text(result, command, load))
    if len(results) == 2:
        print("\n".join(compared(results[0][1], results[1][1])))
    return 0


def per_point_kib(result: dict[str, Any]) -> float:
    """RSS per point after the start-up, in KiB, against before the first setup."""
    points = result["plcs"] * result["points"]
    return (result["rss_mib"][0][1] - result["rss_before_setup_mib"]) * 1024 / points


def tracked_per_point(result: dict[str, Any]) -> float:
    """Objects the GC tracks per point at the end, against before the first setup."""
    points = result["plcs"] * result["points"]
    return (result["gc_tracked"] - result["gc_tracked_before_setup"]) / points


def forced_median(result: dict[str, Any]) -> float:
    """The median CPU time of the full collections forced at the end, in ms."""
    forced = result["gc_forced_cpu_ms"]
    return float(forced[len(forced) // 2])


def compared(before: dict[str, Any], after: dict[str, Any]) -> list[str]:
    """Return the figures item 7 of issue 24 compares, before and after, one line each."""
    rows = [
        ("RSS per point (KiB)", per_point_kib(before), per_point_kib(after)),
        ("longest full collection (ms)", before["gc_gen2_max_ms"], after["gc_gen2_max_ms"]),
        (
            "longest full collection, CPU (ms)",
            before["gc_gen2_max_cpu_ms"],
            after["gc_gen2_max_cpu_ms"],
        ),
        ("full collections", before["gc_gen2"], after["gc_gen2"]),
        ("forced full collection, median CPU (ms)", forced_median(before), forced_median(after)),
        ("GC-tracked objects per point", tracked_per_point(before), tracked_per_point(after)),
        ("longest loop stall (ms)", before["lag_max_ms"], after["lag_max_ms"]),
        ("a poll's longest hold (ms)", before["hold_max_ms"], after["hold_max_ms"]),
    ]
    lines = ["# before -> after:"]
    lines += [
        f"  {name}: {old:.1f} -> {new:.1f} ({(new - old) / old * 100 if old else 0:+.0f} %)"
        for name, old, new in rows
    ]
    return lines


if __name__ == "__main__":
    sys.exit(main())
