"""What this machine has: its cores and its available memory — the one place the code asks
the host, so that a test can set both (monkeypatch `solver.host.cpu_count` and
`solver.host.available_memory_bytes`) and depend on no machine."""

from __future__ import annotations

import math
import os
from pathlib import Path


def cpu_count() -> int:
    """Cores this process may run on (its CPU affinity where the system says, else all)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


def available_memory_bytes() -> float:
    """Memory available to a new process, bytes: MemAvailable (Linux), else the physical memory,
    else infinity (unknown: nothing is refused for memory)."""
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                return float(line.split()[1]) * 1024.0
    except (OSError, ValueError, IndexError):
        pass
    try:
        return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):
        return math.inf
