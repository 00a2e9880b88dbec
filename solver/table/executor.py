"""Run independent work units: in this process, on a local process pool, or on Dask.

Units are pure functions of their arguments, results are collected by the caller in unit
order, so the table is identical whatever the number of workers or where they run.
`on_result(index, result)` is called in the parent as each unit finishes (to persist it);
a tqdm bar shows progress and ETA.
"""

from __future__ import annotations

import logging
import multiprocessing
import os
from concurrent.futures import ProcessPoolExecutor, as_completed
from typing import Any, Callable, Sequence

from tqdm import tqdm

log = logging.getLogger("inkbsdf.tables")


def default_workers() -> int:
    """Local worker processes by default: one per core."""
    return max(1, os.cpu_count() or 1)


def run_units(fn: Callable, units: Sequence[Any], *, workers: int = 1, scheduler: str | None = None,
              desc: str = "units", on_result: Callable[[int, Any], None] | None = None,
              progress: bool = True) -> list:
    """Evaluate fn(unit) for every unit; return the results in unit order."""
    results: list = [None] * len(units)
    if not units:
        return results
    bar = tqdm(total=len(units), desc=desc, unit="unit", disable=not progress, leave=False)

    def done(i: int, res: Any) -> None:
        results[i] = res
        if on_result is not None:
            on_result(i, res)
        bar.update(1)

    try:
        if scheduler:
            from distributed import Client, as_completed as dask_completed

            with Client(scheduler) as client:
                futures = client.map(fn, list(units), pure=False)
                index = {f.key: i for i, f in enumerate(futures)}
                for fut, res in dask_completed(futures, with_results=True):
                    done(index[fut.key], res)
        elif workers <= 1 or len(units) == 1:
            for i, unit in enumerate(units):
                done(i, fn(unit))
        else:
            # spawn, not fork: the caller may be a multithreaded process (a Mitsuba scene load);
            # each unit carries its own FFT thread count
            with ProcessPoolExecutor(max_workers=workers,
                                     mp_context=multiprocessing.get_context("spawn")) as pool:
                futures = {pool.submit(fn, unit): i for i, unit in enumerate(units)}
                for fut in as_completed(futures):
                    done(futures[fut], fut.result())
    finally:
        bar.close()
    return results
