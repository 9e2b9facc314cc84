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
}


def main() -> int:
    """Run the vendor's simulator until standard input closes."""
    return asyncio.run(run([sys.argv[1]], 0, as_json=True, control=True, options=OPTIONS))


if __name__ == "__main__":
    sys.exit(main())
