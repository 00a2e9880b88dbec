"""What a stranger measures: the README's two commands and the default particle table from a fresh
clone with empty caches, each time beside the machine yardstick of the same run.

    python -m benchmarks.bench_fresh                 # clone HEAD, make demo, one table, make test
    python -m benchmarks.bench_fresh --steps demo    # a part (demo, table, test)

The clone is `git clone <this repo> <tmp>/fresh` of the committed HEAD (uncommitted edits are not
measured). The commands run with HOME set to an empty folder, so that Dr.Jit's kernel cache
(~/.drjit) and the table cache (~/.cache/inkbsdf) start empty, as on a new machine; the Python
that makes the virtual environment is this one's base interpreter. The yardstick
(`../shared/bench/yardstick.py`: 200 FFTs of 2×64³, ≈ 0.9 s on a quiet 2-core machine) runs
before and after; each time is printed in seconds and in yardsticks (time / mean yardstick), so
a busy or another machine can be compared. Run it with nothing else on the machine.
"""

from __future__ import annotations

import argparse
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
# the shared yardstick beside the checkout; the same measurement in benchmarks/yardstick.py otherwise
_SHARED = REPO.parent / "shared" / "bench" / "yardstick.py"
YARDSTICK = _SHARED if _SHARED.is_file() else REPO / "benchmarks" / "yardstick.py"
STEPS = ("demo", "table", "test")
# The default particle table of the README (docs/tables.md): what `ink-tables build` makes with
# every default for this ink and these grains.
TABLE_ARGS = ("build", "--ink", "Y7.5+B7.5", "--particles", "sphere:300", "--no-progress")


def yardstick(path: Path) -> float:
    """Seconds of the yardstick, run by this interpreter (numpy and scipy are what it times)."""
    out = subprocess.run([sys.executable, str(path)], check=True, capture_output=True, text=True)
    return float(out.stdout.split()[-1])


def timed(cmd: list[str], cwd: Path, env: dict, log: Path) -> tuple[float, int]:
    """(wall seconds, exit status) of one command, its output to `log`."""
    t0 = time.perf_counter()
    with open(log, "w") as fh:
        rc = subprocess.run(cmd, cwd=cwd, env=env, stdout=fh, stderr=subprocess.STDOUT).returncode
    return time.perf_counter() - t0, rc


def machine() -> str:
    cpu = next((ln.split(":", 1)[1].strip() for ln in Path("/proc/cpuinfo").read_text().splitlines()
                if ln.startswith("model name")), platform.processor()) if Path("/proc/cpuinfo").exists() else ""
    return f"{os.cpu_count()} cores, {cpu}, {platform.system()} {platform.release()}"


def main(argv: list[str]) -> int:
    p = argparse.ArgumentParser(prog="python -m benchmarks.bench_fresh", description=__doc__.split("\n\n")[0])
    p.add_argument("--steps", default=",".join(STEPS), help=f"comma list of {', '.join(STEPS)}")
    p.add_argument("--yardstick", type=Path, default=YARDSTICK, help="the yardstick script")
    p.add_argument("--keep", action="store_true", help="keep the clone (its logs) after the run")
    args = p.parse_args(argv)
    steps = [s for s in args.steps.split(",") if s]
    bad = [s for s in steps if s not in STEPS]
    if bad:
        print(f"--steps: unknown {bad}; choose from {', '.join(STEPS)}", file=sys.stderr)
        return 2
    if not args.yardstick.is_file():
        print(f"--yardstick: {args.yardstick} not found; give the path of shared/bench/yardstick.py",
              file=sys.stderr)
        return 2
    head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=REPO, check=True,
                          capture_output=True, text=True).stdout.strip()
    tmp = Path(tempfile.mkdtemp(prefix="inkbsdf-fresh-"))
    fresh, home = tmp / "fresh", tmp / "home"
    home.mkdir()
    subprocess.run(["git", "clone", "-q", str(REPO), str(fresh)], check=True)
    base_python = Path(sys.base_prefix) / "bin" / "python3"
    env = {k: v for k, v in os.environ.items() if not k.startswith(("INKBSDF", "VIRTUAL_ENV"))}
    env["HOME"] = str(home)
    make = ["make", f"PY={base_python}"]
    print(f"machine: {machine()}; commit {head}; clone {fresh}; HOME={home} (empty: no ~/.drjit, "
          "no table cache)", flush=True)

    y0 = yardstick(args.yardstick)
    print(f"yardstick before: {y0:.3f} s", flush=True)
    rows = []
    t, rc = timed(make + ["venv"], fresh, env, tmp / "venv.log")
    rows.append(("bootstrap (make venv: venv + pip install)", t, rc))
    for step in steps:
        if step == "demo":
            t, rc = timed(make + ["demo"], fresh, env, tmp / "demo.log")
            rows.append(("make demo (LLVM check, 6 demo tables, 640×512 render)", t, rc))
        elif step == "table":
            out = tmp / "particle.npz"
            t, rc = timed([str(fresh / ".venv" / "bin" / "ink-tables"), *TABLE_ARGS, "-o", str(out)],
                          fresh, env, tmp / "table.log")
            rows.append(("default particle table (Y7.5+B7.5, sphere:300), empty cache", t, rc))
        else:
            t, rc = timed(make + ["test"], fresh, env, tmp / "test.log")
            tail = (tmp / "test.log").read_text().strip().splitlines()[-1:]
            rows.append((f"make test ({tail[0] if tail else '?'})", t, rc))
        print(f"  {rows[-1][0]}: {rows[-1][1]:.1f} s (exit {rows[-1][2]})", flush=True)
    y1 = yardstick(args.yardstick)
    y = 0.5 * (y0 + y1)
    print(f"yardstick after: {y1:.3f} s\n")
    print("| step | wall | wall / yardstick | exit |")
    print("|---|---|---|---|")
    for name, t, rc in rows:
        print(f"| {name} | {t:.1f} s | {t / y:.0f} | {rc} |")
    print(f"\nyardstick {y0:.3f} s before, {y1:.3f} s after (mean {y:.3f} s); logs in {tmp}")
    if not args.keep:
        subprocess.run(["rm", "-rf", str(fresh / ".venv"), str(home)])
    return 1 if any(rc for _, _, rc in rows) else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
