"""Interrupts of a command: SIGINT (Ctrl-C) and SIGTERM, both as exceptions of the main thread.

Inside `raising()` (a command's run) SIGTERM becomes `Terminated`, a KeyboardInterrupt, so
every cleanup written for Ctrl-C (temp files removed, worker processes killed; docs/tables.md
"Interrupts") runs for it too and the command says one line and exits 128 + 15; what arrived is
remembered, so an interrupt that C code turned into another error (an import cut short) is
still told as the interrupt.  `deferred()` holds both signals back through a short
section that must not be cut in half (starting or killing worker processes): a signal that
arrives inside it is raised when the section ends.  Python runs signal handlers in the main
thread only, so off the main thread both are no-ops (nothing can interrupt such a thread).
"""

from __future__ import annotations

import contextlib
import signal
import threading

SIGNALS = (signal.SIGINT, signal.SIGTERM)


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised in the main thread like Ctrl-C's KeyboardInterrupt."""

    def __init__(self, signum: int = signal.SIGTERM):
        super().__init__(f"terminated (signal {signum})")
        self.signum = signum


def exit_status(exc: KeyboardInterrupt) -> int:
    """The shell's exit status of an interrupted command: 128 + the signal's number."""
    return 128 + getattr(exc, "signum", signal.SIGINT)


#: the signals received in the current `raising()` block, in order
_received: list[int] = []


def _raise(signum, _frame):
    _received.append(signum)
    raise Terminated(signum) if signum == signal.SIGTERM else KeyboardInterrupt()


def received() -> KeyboardInterrupt | None:
    """The interrupt a signal raised in the current `raising()` block, if one came: an
    exception that C code made of it (an import cut short says ImportError) is still an
    interrupt, not a fault."""
    if not _received:
        return None
    return Terminated(_received[-1]) if _received[-1] == signal.SIGTERM else KeyboardInterrupt()


def _in_main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


@contextlib.contextmanager
def raising():
    """For the block, in the main thread: SIGINT raises KeyboardInterrupt and SIGTERM raises
    `Terminated`, each remembered (`received`); the handlers before are restored after it."""
    if not _in_main_thread():
        yield
        return
    _received.clear()
    previous = {s: signal.signal(s, _raise) for s in SIGNALS}
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, signal.SIG_DFL if handler is None else handler)   # None: set outside Python
        _received.clear()                  # what came is this block's: a later command starts clean


@contextlib.contextmanager
def deferred():
    """SIGINT and SIGTERM that arrive in the block are delivered when it ends (to the handlers
    in place before it), so the block runs to its end."""
    if not _in_main_thread():
        yield
        return
    caught: list[int] = []
    previous = {s: signal.signal(s, lambda signum, _frame: caught.append(signum)) for s in SIGNALS}
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, signal.SIG_DFL if handler is None else handler)   # None: set outside Python
        for s in dict.fromkeys(caught):
            signal.raise_signal(s)
