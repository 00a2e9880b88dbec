"""solver.interrupts: SIGTERM as an interrupt inside a command's run, signals held back through
a section that must not be cut in half (docs/tables.md "Interrupts")."""

import pytest


def test_sigterm_is_an_interrupt_only_inside_raising_and_deferred_holds_signals_back():
    """solver.interrupts: inside `raising()` SIGTERM raises Terminated (a KeyboardInterrupt,
    exit status 143) and is remembered; `deferred()` delivers a signal when its block ends, not
    in the middle; outside, the handlers before are back and nothing is remembered."""
    import signal

    from solver.interrupts import Terminated, deferred, exit_status, raising, received

    before = signal.getsignal(signal.SIGTERM)
    steps = []
    with raising():
        with pytest.raises(Terminated) as info:
            with deferred():
                signal.raise_signal(signal.SIGTERM)
                steps.append("after the signal, inside the block")
        assert steps and exit_status(info.value) == 143 and isinstance(received(), Terminated)
        with pytest.raises(KeyboardInterrupt):
            signal.raise_signal(signal.SIGINT)
        assert exit_status(received()) == 130
    assert received() is None and signal.getsignal(signal.SIGTERM) == before
