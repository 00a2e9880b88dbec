"""`make bench`: every speed/accuracy study, one after the other (not part of the tests).

    python -m benchmarks            # all
    python -m benchmarks wave render  # some (module names without the bench_ prefix)
"""

from __future__ import annotations

import importlib
import sys
import time

STUDIES = ("geometry", "wave", "render", "tables", "findings", "polarisation", "printing", "figures", "gradients", "variants",
           "polarized", "separation", "vector", "convergence")


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
