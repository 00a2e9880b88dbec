"""The local worker processes of table builds (solver/table/workers.py): results in unit order
whatever the number of workers, a unit's error raised in the parent with its type and its
worker's traceback, a worker killed from outside told in one line, and no worker left after a
failure or a close."""

import os

import pytest

from solver.table.executor import run_units
from solver.table.workers import RemoteTraceback, WorkerLost, WorkerPool
from worker_units import fails_at_three, killed_at_two, odd_error_at_one, pid, square


@pytest.fixture(scope="module")
def pool():
    """Two workers shared by the tests that leave them running (spawning costs ~1 s)."""
    shared = WorkerPool(2)
    yield shared
    shared.close()


def _alive(_pool=None) -> list:
    """This process's live worker processes (whatever the pool thinks it holds)."""
    import multiprocessing

    return [p for p in multiprocessing.active_children() if p.name.startswith("inkbsdf-table-worker")]


def test_results_in_unit_order_on_any_number_of_workers(pool):
    units = list(range(7))
    expected = [u * u for u in units]
    assert run_units(square, units, workers=1, progress=False) == expected
    assert run_units(square, units, pool=pool, progress=False) == expected


def test_a_pool_serves_several_runs_with_the_same_workers_and_closes(pool):
    first, second = set(), set()
    pool.run(pid, range(6), lambda i, r: first.add(r))
    pool.run(pid, range(6), lambda i, r: second.add(r))
    assert first == second and len(first) == 2 and os.getpid() not in first
    workers = [w.process for w in pool._workers]
    pool.close()
    assert not any(p.is_alive() for p in workers) and not pool._workers and not _alive()


def test_a_units_error_is_raised_here_with_its_traceback_and_the_workers_are_killed(pool):
    with pytest.raises(ZeroDivisionError, match="unit three") as info:
        pool.run(fails_at_three, range(6), lambda i, r: None)
    assert isinstance(info.value.__cause__, RemoteTraceback) and "fails_at_three" in str(info.value.__cause__)
    assert not _alive(pool) and not pool._workers


def test_an_error_that_cannot_be_rebuilt_here_is_said_by_name(pool):
    with pytest.raises(RuntimeError, match="TwoArgError: x and y"):
        run_units(odd_error_at_one, [0, 1, 2], pool=pool, progress=False)


def test_a_worker_killed_from_outside_is_one_clear_error(pool):
    with pytest.raises(WorkerLost, match=r"died: killed by signal 9 \(out of memory\?\)"):
        pool.run(killed_at_two, range(5), lambda i, r: None)
    assert not _alive(pool)


def test_an_error_of_the_caller_stops_the_workers(pool):
    """`done` (storing a part) failing — a full disk — kills the workers too."""

    def done(i, r):
        raise OSError(28, "No space left on device")

    with pytest.raises(OSError, match="No space"):
        pool.run(square, range(4), done)
    assert not _alive(pool)

