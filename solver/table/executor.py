"""Run independent work units: in this process, on a local process pool, or on Dask.

Units are pure functions of their arguments, results are collected by the caller in unit
order, so the table is identical whatever the number of workers or where they run.
`on_result(index, result)` is called in the parent as each unit finishes (to persist it);
a tqdm bar shows progress and ETA.

No worker outlives its build: local workers ask the kernel to kill them when their parent dies
(Linux PR_SET_PDEATHSIG, so even `kill -9` of the build leaves nothing behind), ignore Ctrl-C
(the parent stops them), and are killed when the parent is interrupted or fails.
"""

from __future__ import annotations

import contextlib
import ctypes
import logging
import multiprocessing
import os
import re
import signal
import socket
import warnings
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from typing import Any, Callable, Sequence
from urllib.parse import urlparse

from tqdm import tqdm

log = logging.getLogger("inkbsdf.tables")

_PR_SET_PDEATHSIG = 1


class SchedulerError(ValueError):
    """The Dask scheduler named by --scheduler cannot be reached."""


def default_workers() -> int:
    """Local worker processes by default: one per core."""
    return max(1, os.cpu_count() or 1)


def _init_worker(parent_pid: int) -> None:
    """In each pool worker: die with the parent, leave Ctrl-C to the parent."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    except (OSError, AttributeError):      # not Linux: the parent's cleanup below still applies
        pass
    if os.getppid() != parent_pid:         # the parent died before prctl took effect
        os._exit(1)


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


def _stop(pool: ProcessPoolExecutor) -> None:
    """Cancel what has not started and kill the workers now (an interrupt or a failure)."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    for proc in processes:
        if proc.is_alive():
            proc.kill()
    for proc in processes:
        proc.join(timeout=5)


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
    """A process pool for several `run_units` calls (a table's stages, a figure's tables):
    workers are spawned once — spawning and importing the solver costs about a second each.
    Spawn, not fork: the caller may be a multithreaded process (a Mitsuba scene load); each unit
    carries its own FFT thread count.  On an interrupt or a failure the workers are killed."""
    pool = ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn"),
                               initializer=_init_worker, initargs=(os.getpid(),))
    try:
        yield pool
    except BaseException:
        _stop(pool)
        raise
    pool.shutdown(wait=True)


def _run_pool(fn, units, pool, done) -> None:
    futures = {pool.submit(fn, unit): i for i, unit in enumerate(units)}
    pending = set(futures)
    try:
        while pending:
            finished, pending = wait(pending, return_when=FIRST_COMPLETED)
            for fut in finished:
                done(futures[fut], fut.result())
    except BaseException:
        _stop(pool)
        raise


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
              progress: bool = True, pool: ProcessPoolExecutor | None = None) -> list:
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
            _run_pool(fn, units, pool, done)
        elif usable_workers(workers) <= 1 or len(units) == 1:
            for i, unit in enumerate(units):
                done(i, fn(unit))
        else:
            with local_pool(min(workers, len(units))) as own:
                _run_pool(fn, units, own, done)
    finally:
        bar.close()
    return results
