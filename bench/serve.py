"""Serve one simulator for the benchmarks: `python -m bench.serve VENDOR [POINTS]`, driven on stdin.

Like `python -m simulators --only VENDOR --port 0 --json --control`, with the memory sizes the
benchmark's POINTS points need (1,000 unless given).
"""

from __future__ import annotations

import asyncio
import sys
from typing import Any

from simulators.__main__ import run


def options(points: int) -> dict[str, dict[str, Any]]:
    """The simulators' options for the benchmark's mix of `points` points (at least 1,000)."""
    points = max(points, 1000)
    return {
        # The mix takes 8 bytes every 4 points; the default DB1 of 1 KB holds far fewer.
        "s7": {"dbs": {1: max(8192, 2 * points + 64)}},
        "plcnext": {"bench": points},  # Bench.Value0 .. (none by default)
        "tecomat": {"bench": points},  # BENCH.V0 ..
        # Files N10, F11, B12 and T13 of `points` elements: the mix reads up to T13:<points - 1>.
        "softplc": {"bench": points, "tls": False, "put_auth": False},
    }


def main() -> int:
    """Run the vendor's simulator until standard input closes."""
    points = int(sys.argv[2]) if len(sys.argv) > 2 else 1000
    return asyncio.run(run([sys.argv[1]], 0, as_json=True, control=True, options=options(points)))


if __name__ == "__main__":
    sys.exit(main())
