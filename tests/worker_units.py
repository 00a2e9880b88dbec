"""Work units for tests/test_table_workers.py, in a module of their own that imports only the
standard library: a spawned worker imports it to run them, so it must load fast."""

import os
import signal


def square(u):
    return u * u


def pid(_u):
    return os.getpid()


class TwoArgError(Exception):
    """An error that pickles but does not unpickle (its __init__ wants two arguments)."""

    def __init__(self, a, b):
        super().__init__(f"{a} and {b}")


def fails_at_three(u):
    if u == 3:
        raise ZeroDivisionError("unit three")
    return u


def odd_error_at_one(u):
    if u == 1:
        raise TwoArgError("x", "y")
    return u


def killed_at_two(u):
    if u == 2:
        os.kill(os.getpid(), signal.SIGKILL)
    return u
