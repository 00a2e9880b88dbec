"""Interrupts at random moments: a small `ink-tables build` is sent SIGINT or SIGTERM at a random
moment, many times, under CPU load; each must exit within EXIT_LIMIT_S with its one line, exit
status 130 / 143, no traceback, no temp file, no output file and no process of its process
group left (docs/tables.md "Interrupts").

    python -m benchmarks interrupts              # 50 interrupts; prints each and the summary
    python -m benchmarks.bench_interrupts --count 10 --seed 3

tests/test_hardening_tables.py runs `stress` a few times.  Times under load are not a quiet
machine's: the yardstick (a fixed FFT workload, seconds) is printed beside them.
"""

from __future__ import annotations

import argparse
import os
import random
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

from benchmarks.yardstick import yardstick_s

CLI = [sys.executable, "-m", "solver.apps.cli"]
#: a build long enough (~6 s on 2 cores, idle) that a moment drawn in [EARLIEST_S, latest_s] falls
#: inside it: loading, spawning the workers, geometry, solves, storing parts
BUILD = ["build", "--ink", "Y7.5+B7.5", "--particles", "sphere:300", "--wavelengths", "400:700:20",
         "--angles", "4", "--grid", "24", "24", "12", "--realizations", "1", "--azimuths", "2",
         "--tier", "full", "--workers", "2", "--no-progress"]
#: the earliest moment drawn (s after the process starts): before it the interpreter itself is
#: starting and a signal is Python's own (docs/tables.md "Interrupts")
EARLIEST_S = 0.25
EXIT_LIMIT_S = 5.0
#: a command that has not exited this long after its signal has hung (it is then killed)
HANG_S = 60.0


def process_group(pgid: int) -> list[str]:
    """Command lines of the live (non-zombie) processes in a process group (Linux /proc)."""
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
            if int(fields[2]) == pgid and fields[0] != "Z":
                found.append((stat.parent / "cmdline").read_bytes().replace(b"\0", b" ").decode()[:120])
        except (OSError, IndexError, ValueError):
            continue
    return found


@dataclass
class Outcome:
    delay_s: float
    signal: int
    status: int | None                 # None: hung (killed after HANG_S)
    exit_s: float                      # from the signal to the exit
    stderr: str
    left: list[str] = field(default_factory=list)   # processes of its group alive EXIT_LIMIT_S after
    litter: list[str] = field(default_factory=list)  # temp files, or the output of an interrupted build

    @property
    def finished_first(self) -> bool:
        return self.status == 0

    def problems(self) -> list[str]:
        """What is wrong with this interrupt (empty: all well, or it finished before the signal)."""
        if self.finished_first:
            return []
        said = [line for line in self.stderr.splitlines() if "interrupted" in line or "terminated" in line]
        wrong = []
        if self.status != 128 + self.signal:
            wrong.append(f"exit status {self.status}, expected {128 + self.signal}")
        if self.exit_s > EXIT_LIMIT_S:
            wrong.append(f"took {self.exit_s:.1f} s to exit")
        if wrong or len(said) != 1 or "Traceback" in self.stderr or "Exception ignored" in self.stderr:
            wrong.append("stderr: " + " | ".join(self.stderr.strip().splitlines()[-6:]))
        if self.left:
            wrong.append(f"left {self.left}")
        if self.litter:
            wrong.append(f"left files {self.litter}")
        return wrong


def interrupt_build(folder: Path, delay_s: float, sig: int) -> Outcome:
    """Start BUILD (a new process group, its cache in `folder`), send `sig` after `delay_s`."""
    cache, out = folder / "cache", folder / "t.npz"
    proc = subprocess.Popen(CLI + BUILD + ["--cache", str(cache), "-o", str(out)], stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        proc.wait(delay_s)
        return Outcome(delay_s, sig, proc.returncode, 0.0, proc.stderr.read())
    except subprocess.TimeoutExpired:
        pass
    t0 = time.perf_counter()
    proc.send_signal(sig)
    try:
        _, err = proc.communicate(timeout=HANG_S)
        status = proc.returncode
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        _, err = proc.communicate()
        status = None
    exit_s = time.perf_counter() - t0
    deadline = time.monotonic() + EXIT_LIMIT_S
    while process_group(proc.pid) and time.monotonic() < deadline:
        time.sleep(0.05)
    left = process_group(proc.pid)
    if left:
        os.killpg(proc.pid, signal.SIGKILL)
    litter = [str(p) for p in cache.rglob("*.tmp")] + ([str(out)] if out.exists() else [])
    return Outcome(delay_s, sig, status, exit_s, err, left, litter)


class cpu_load:
    """`n` busy processes (their own process group) for the block: the load the deadlock needed."""

    def __init__(self, n: int):
        self.n, self.procs = n, []

    def __enter__(self):
        busy = "import os\nparent = os.getppid()\nwhile os.getppid() == parent:\n    pass"   # ends with us
        self.procs = [subprocess.Popen([sys.executable, "-c", busy], start_new_session=True) for _ in range(self.n)]
        return self

    def __exit__(self, *exc):
        for p in self.procs:
            p.kill()
            p.wait()


def stress(count: int, seed: int, latest_s: float, load: int, folder: Path, report=None) -> list[Outcome]:
    """`count` interrupts at moments uniform in [EARLIEST_S, latest_s], SIGINT and SIGTERM drawn
    at random, under `load` busy processes; `report(k, outcome)` after each."""
    rng = random.Random(seed)
    outcomes = []
    with cpu_load(load):
        for k in range(count):
            sig = rng.choice((signal.SIGINT, signal.SIGTERM))
            outcome = interrupt_build(folder / f"run{k}", rng.uniform(EARLIEST_S, latest_s), sig)
            outcomes.append(outcome)
            if report:
                report(k, outcome)
    return outcomes


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks.bench_interrupts", description=__doc__.split("\n")[0])
    parser.add_argument("--count", type=int, default=50, help="interrupts (default 50)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--load", type=int, default=2, help="busy processes beside the builds (default 2)")
    args = parser.parse_args(argv)
    print(f"yardstick {yardstick_s():.3f} s, load average {os.getloadavg()[0]:.1f}", flush=True)
    with tempfile.TemporaryDirectory(prefix="inkbsdf-interrupts-") as tmp:
        with cpu_load(args.load):
            t0 = time.perf_counter()
            whole = interrupt_build(Path(tmp) / "whole", 1e9, signal.SIGINT)
            build_s = time.perf_counter() - t0
        print(f"an uninterrupted build: {build_s:.1f} s under load {args.load} (exit {whole.status}); "
              f"moments drawn in [{EARLIEST_S}, {build_s:.1f}] s", flush=True)

        def report(k, o):
            bad = o.problems()
            what = "finished first" if o.finished_first else f"exit {o.status} after {o.exit_s:.2f} s"
            print(f"{k:3d}  {signal.Signals(o.signal).name:7s} at {o.delay_s:5.2f} s: {what}"
                  + (f"  PROBLEM: {'; '.join(bad)}" if bad else ""), flush=True)

        outcomes = stress(args.count, args.seed, build_s, args.load, Path(tmp), report)
    hit = [o for o in outcomes if not o.finished_first]
    bad = [o for o in hit if o.problems()]
    times = sorted(o.exit_s for o in hit)
    print(f"{len(hit)} interrupted ({len(outcomes) - len(hit)} finished first), {len(bad)} with a problem; "
          f"exit after the signal: median {statistics.median(times):.2f} s, max {times[-1]:.2f} s "
          f"(limit {EXIT_LIMIT_S} s); processes left: {sum(len(o.left) for o in hit)}; "
          f"yardstick {yardstick_s():.3f} s, load average {os.getloadavg()[0]:.1f}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
