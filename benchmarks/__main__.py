"""`make bench`: every speed/accuracy study, one after the other (not part of the tests).

    python -m benchmarks            # all
    python -m benchmarks wave render  # some (module names without the bench_ prefix)
"""

from __future__ import annotations

import importlib
import sys
import time
from pathlib import Path

# Every benchmarks/bench_NAME.py is a study, found by its file name (no list to keep by hand);
# `fresh` (the README's commands from a fresh clone) runs first, the rest alphabetically.
_NAMES = sorted(p.stem[len("bench_"):] for p in Path(__file__).parent.glob("bench_*.py"))
STUDIES = tuple(sorted(_NAMES, key=lambda n: (n != "fresh", n)))


def main(argv: list[str]) -> int:
    names = argv or list(STUDIES)
    unknown = [n for n in names if n not in STUDIES]
    if unknown:
        print(f"unknown benchmark(s) {unknown}; choose from {STUDIES}", file=sys.stderr)
        return 2
    for name in names:
        print(f"\n===== benchmarks.bench_{name} =====", flush=True)
        t0 = time.perf_counter()
        importlib.import_module(f"benchmarks.bench_{name}").main([])
        print(f"===== bench_{name}: {time.perf_counter() - t0:.1f} s =====", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
