"""Old code beside new in one run: extract a git revision's sources into a temp folder and run
a command with them first on the path (benchmarks time the two side by side, since machines
are noisy and only a ratio measured in one run means something)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
#: main before this round's work (the last landing of the previous session)
PREVIOUS_ROUND = "32e4d4f"


def extract(rev: str, dest: Path, paths=("solver",)) -> Path | None:
    """`paths` of git revision `rev` under dest, or None (said) when git cannot provide them."""
    try:
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", rev, *paths],
                                 check=True, capture_output=True).stdout
        dest.mkdir(parents=True, exist_ok=True)
        subprocess.run(["tar", "-x", "-C", str(dest)], input=archive, check=True)
    except (OSError, subprocess.CalledProcessError) as err:
        print(f"(baseline {rev} unavailable: {err})")
        return None
    return dest


def environment(tree: Path) -> dict:
    """This process's environment with `tree` first on PYTHONPATH (then the caller's other
    entries, e.g. where optional packages live)."""
    extra = [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep)
             if p and Path(p).resolve() != ROOT]
    return dict(os.environ, PYTHONPATH=os.pathsep.join([str(tree)] + extra))


def run_python(tree: Path, args: list[str], **kw) -> subprocess.CompletedProcess:
    """`python ARGS` with `tree`'s packages first on the path, run in `tree`: `-m` and `-c` put
    the working folder first on sys.path, ahead of PYTHONPATH, so running them from this
    checkout would time this checkout's code instead of the tree's."""
    return subprocess.run([sys.executable, *args], env=environment(tree), cwd=str(tree), check=True, **kw)
