"""Local worker processes for a table's work units, driven from the calling thread alone.

Each worker is a spawned process with a pipe of its own; the parent hands a unit to an idle
worker, waits on the pipes and the processes' sentinels, and takes each result as it comes.
The parent has no helper thread (concurrent.futures' process pool has two: a queue feeder and
a manager), so an interrupt cannot strand one: with that pool an interrupted build under load
deadlocked — the main thread joining the manager, the feeder blocked writing to a pipe that no
killed worker read — and SIGTERM printed "Exception ignored … Bad file descriptor" from a
thread writing to a pipe already closed (docs/tables.md "Interrupts").

Workers die with the parent (Linux PR_SET_PDEATHSIG, so even `kill -9` of the build leaves
nothing behind) and ignore SIGINT and SIGTERM: the parent stops them (`kill`) when it is
interrupted or a unit fails, and a signal sent to the whole process group (Ctrl-C in a
terminal) cannot kill a worker before the parent has said why it stops.  Starting and killing
workers hold SIGINT and SIGTERM back until done (solver.interrupts.deferred), so an interrupt
never leaves a worker half started or unkilled.
"""

from __future__ import annotations

import ctypes
import multiprocessing
import os
import pickle
import signal
import traceback
from dataclasses import dataclass
from multiprocessing.connection import Connection, wait
from typing import Any, Callable, Sequence

from ..interrupts import deferred

_PR_SET_PDEATHSIG = 1
#: seconds a worker gets to leave after being told to (a normal close), and to be reaped after a kill
JOIN_S = 5.0


class WorkerLost(RuntimeError):
    """A worker process died while it held a unit (killed from outside: out of memory?)."""


class RemoteTraceback(Exception):
    """The traceback of a unit's failure in a worker (the `__cause__` of the re-raised error)."""

    def __str__(self):
        return self.args[0]


def _init_worker(parent_pid: int) -> None:
    """In each worker: die with the parent, leave SIGINT and SIGTERM to the parent."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    except (OSError, AttributeError):      # not Linux: a closed pipe (the parent gone) ends the loop
        pass
    if os.getppid() != parent_pid:         # the parent died before prctl took effect
        os._exit(1)


def _serve(conn: Connection, parent_pid: int) -> None:
    """A worker's loop: (fn, unit) in, (True, fn(unit)) or (False, error, traceback) out; None
    or a closed pipe ends it."""
    _init_worker(parent_pid)
    while True:
        try:
            task = conn.recv()
        except (EOFError, OSError):
            return
        if task is None:
            return
        fn, unit = task
        try:
            reply = (True, fn(unit))
        except BaseException as exc:       # the parent decides; this worker stays usable
            reply = (False, _portable(exc), traceback.format_exc())
        try:
            conn.send(reply)
        except (BrokenPipeError, OSError):
            return
        except Exception as exc:           # the result or the error does not pickle (send wrote nothing)
            conn.send((False, RuntimeError(f"a unit's {'result' if reply[0] else 'error'} cannot be sent "
                                           f"back from its worker: {exc}"), traceback.format_exc()))


def _portable(exc: BaseException) -> BaseException:
    """`exc` if it survives pickling both ways (the parent must be able to rebuild it), else a
    RuntimeError saying what it was."""
    try:
        pickle.loads(pickle.dumps(exc))
        return exc
    except Exception:
        return RuntimeError(f"{type(exc).__name__}: {exc}")


@dataclass
class _Worker:
    process: Any              # multiprocessing's SpawnProcess
    conn: Connection

    def lost(self) -> WorkerLost:
        self.process.join(JOIN_S)          # its pipe can close before its exit is seen
        code = self.process.exitcode
        how = (f"killed by signal {-code}" + (" (out of memory?)" if -code == signal.SIGKILL else "")
               if code is not None and code < 0 else f"exit code {code}")
        return WorkerLost(f"a table worker process (pid {self.process.pid}) died: {how}; finished units "
                          "are kept, rerun to resume (with fewer --workers if memory ran out)")


class WorkerPool:
    """Up to `size` spawned worker processes for several `run` calls (started on first need:
    spawning and importing the solver costs about a second each); `close` or `kill` ends them."""

    def __init__(self, size: int):
        self.size = max(1, int(size))
        self._ctx = multiprocessing.get_context("spawn")   # the caller may be multithreaded (a scene load)
        self._workers: list[_Worker] = []

    def _start(self, count: int) -> None:
        while len(self._workers) < min(self.size, count):
            with deferred():
                parent_end, child_end = self._ctx.Pipe(duplex=True)
                process = self._ctx.Process(target=_serve, args=(child_end, os.getpid()), daemon=True,
                                            name=f"inkbsdf-table-worker-{len(self._workers)}")
                try:
                    process.start()
                except BaseException:
                    parent_end.close()
                    raise
                finally:
                    child_end.close()             # the worker holds the only other end: its death closes the pipe
                self._workers.append(_Worker(process, parent_end))

    def run(self, fn: Callable, units: Sequence[Any], done: Callable[[int, Any], None]) -> None:
        """fn(unit) for every unit on the workers, `done(index, result)` here as each ends.  A
        unit's error is raised here (its traceback as the cause) after the workers are killed;
        so is an interrupt, or an error of `done`."""
        try:
            self._start(len(units))
            todo = list(enumerate(units))[::-1]
            idle = list(self._workers)
            busy: dict[Connection, tuple[_Worker, int]] = {}
            while todo or busy:
                while todo and idle:
                    worker, (i, unit) = idle.pop(), todo.pop()
                    try:
                        worker.conn.send((fn, unit))
                    except (BrokenPipeError, ConnectionResetError):
                        raise worker.lost() from None
                    busy[worker.conn] = (worker, i)
                sentinels = {w.process.sentinel: w for w, _ in busy.values()}
                ready = wait(list(busy) + list(sentinels))
                for conn in [r for r in ready if r in busy]:
                    worker, i = busy.pop(conn)
                    try:
                        reply = conn.recv()
                    except (EOFError, OSError):
                        raise worker.lost() from None
                    idle.append(worker)
                    if not reply[0]:
                        error, remote = reply[1], reply[2]
                        raise error from RemoteTraceback(remote)
                    done(i, reply[1])
                for sentinel in [r for r in ready if r in sentinels]:
                    worker = sentinels[sentinel]
                    if worker.conn in busy and not worker.conn.poll():
                        raise worker.lost()
        except BaseException:
            self.kill()
            raise

    def kill(self) -> None:
        """Kill every worker now (an interrupt or a failure) and reap it."""
        with deferred():
            workers, self._workers = self._workers, []
            for w in workers:
                if w.process.is_alive():
                    w.process.kill()
            for w in workers:
                w.process.join(JOIN_S)
                w.conn.close()

    def close(self) -> None:
        """Tell every worker to leave, reap it (killed if it does not leave within JOIN_S)."""
        with deferred():
            workers, self._workers = self._workers, []
            for w in workers:
                try:
                    w.conn.send(None)
                except OSError:
                    pass
            for w in workers:
                w.process.join(JOIN_S)
                if w.process.is_alive():
                    w.process.kill()
                    w.process.join(JOIN_S)
                w.conn.close()
