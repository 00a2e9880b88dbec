"""Run independent work units: in this process, on a local process pool, or on Dask.

Units are pure functions of their arguments, results are collected by the caller in unit
order, so the table is identical whatever the number of workers or where they run.
`on_result(index, result)` is called in the parent as each unit finishes (to persist it);
a tqdm bar shows progress and ETA.

No worker outlives its build: local workers (solver.table.workers) die with their parent, leave
Ctrl-C and SIGTERM to it, and are killed when it is interrupted or fails.
"""

from __future__ import annotations

import contextlib
import logging
import re
import socket
import warnings
from typing import Any, Callable, Sequence
from urllib.parse import urlparse

from tqdm import tqdm

from ..host import cpu_count
from .workers import WorkerPool

log = logging.getLogger("inkbsdf.tables")



class SchedulerError(ValueError):
    """The Dask scheduler named by --scheduler cannot be reached."""


def default_workers() -> int:
    """Local worker processes by default: one per core."""
    return cpu_count()


def check_scheduler(address: str, timeout_s: float = 5.0) -> None:
    """Refuse an unreachable Dask scheduler in seconds, with one line (before any work)."""
    url = urlparse(address if "://" in address else f"tcp://{address}")
    try:
        port = url.port
    except ValueError:
        port = None
    if url.scheme not in ("tcp", "tls") or not url.hostname or not port:
        raise SchedulerError(f"--scheduler {address!r}: expected tcp://HOST:PORT")
    try:
        with socket.create_connection((url.hostname, port), timeout=timeout_s):
            pass
    except OSError as exc:
        raise SchedulerError(f"--scheduler {address}: cannot reach the Dask scheduler ({exc.strerror or exc}); "
                             "start it (`dask scheduler`) or leave out --scheduler to use local workers") from None


def main_is_guarded() -> bool:
    """False when the running script has no `if __name__ == "__main__":` guard (spawned pool
    workers re-run a script's top level, which would build again, recursively), or is no file
    that a worker could re-run (a script read from standard input)."""
    import __main__

    path = getattr(__main__, "__file__", None)
    spec = getattr(__main__, "__spec__", None)
    if path is None or (spec is not None and spec.name.endswith(".__main__")):
        return True          # interactive, or `python -m package`: spawn does not re-run either
    try:
        text = open(path, encoding="utf-8", errors="replace").read()
    except OSError:
        return False         # `python - < script`: spawned workers cannot re-read "<stdin>"
    return re.search(r"__name__\s*==\s*['\"]__main__['\"]", text) is not None


def usable_workers(workers: int) -> int:
    """`workers`, or 1 with a warning when the calling script cannot spawn workers safely."""
    if workers > 1 and not main_is_guarded():
        warnings.warn("inkbsdf: this script has no `if __name__ == \"__main__\":` guard (or is read from "
                      "standard input), so table workers cannot be spawned safely; building in one process",
                      stacklevel=3)
        return 1
    return workers


@contextlib.contextmanager
def local_pool(workers: int):
    """A WorkerPool for several `run_units` calls (a table's stages, a figure's tables): workers
    are spawned once — spawning and importing the solver costs about a second each.  Spawn,
    not fork: the caller may be a multithreaded process (a Mitsuba scene load); each unit
    carries its own FFT thread count.  On an interrupt or a failure the workers are killed."""
    pool = WorkerPool(workers)
    try:
        yield pool
    except BaseException:
        pool.kill()
        raise
    pool.close()

def _run_dask(fn, units, scheduler, done) -> None:
    from distributed import Client, as_completed as dask_completed

    check_scheduler(scheduler)
    with Client(scheduler, timeout="10s") as client:
        futures = client.map(fn, list(units), pure=False)
        index = {f.key: i for i, f in enumerate(futures)}
        try:
            for fut, res in dask_completed(futures, with_results=True):
                done(index[fut.key], res)
        except BaseException:
            client.cancel(futures)
            raise


def run_units(fn: Callable, units: Sequence[Any], *, workers: int = 1, scheduler: str | None = None,
              desc: str = "units", on_result: Callable[[int, Any], None] | None = None,
              progress: bool = True, pool: WorkerPool | None = None) -> list:
    """Evaluate fn(unit) for every unit; return the results in unit order (on `pool` when
    given, else on a pool of `workers` processes made for this call, or in this process)."""
    results: list = [None] * len(units)
    if not units:
        return results
    bar = tqdm(total=len(units), desc=desc, unit="unit", disable=None if progress else True, leave=False)

    def done(i: int, res: Any) -> None:
        results[i] = res
        if on_result is not None:
            on_result(i, res)
        bar.update(1)

    try:
        if scheduler:
            _run_dask(fn, units, scheduler, done)
        elif pool is not None:
            pool.run(fn, units, done)
        elif usable_workers(workers) <= 1 or len(units) == 1:
            for i, unit in enumerate(units):
                done(i, fn(unit))
        else:
            with local_pool(min(workers, len(units))) as own:
                own.run(fn, units, done)
    finally:
        bar.close()
    return results
