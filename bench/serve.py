"""Serve one simulator for the benchmarks: `python -m bench.serve VENDOR` (stdin controls it).

Like `python -m simulators --only VENDOR --port 0 --json --control`, with the memory sizes the
benchmark's points need.
"""

from __future__ import annotations

import asyncio
import sys
from typing import Any

from simulators.__main__ import run

OPTIONS: dict[str, dict[str, Any]] = {
    "s7": {"dbs": {1: 8192}},  # the default DB1 of 1 KB holds fewer than 1,000 points
    "plcnext": {"bench": 1000},  # Bench.Value0 .. Bench.Value999 (none by default)
    # Files N10, F11, B12 and T13 of 1,000 elements: the 1,000-point mix reads up to T13:999.
    "softplc": {"bench": 1000, "tls": False, "put_auth": False},
}


def main() -> int:
    """Run the vendor's simulator until standard input closes."""
    return asyncio.run(run([sys.argv[1]], 0, as_json=True, control=True, options=OPTIONS))


if __name__ == "__main__":
    sys.exit(main())
