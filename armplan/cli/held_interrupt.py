"""Ctrl-C while a command loads is held, then reported in one line.

``armplan`` imports every command before it parses its arguments (about
0.7 s: libqi, pinocchio, pydantic, zenoh). A ``KeyboardInterrupt`` raised
in the middle of that printed a traceback, or came out of a C extension's
initialisation as an ``ImportError``. So SIGINT is blocked while the
commands load: one that arrives waits, pending, and is taken when the
loading ends, and the command exits 130 ("interrupted") without running.

A blocked signal stays blocked, and pending, across ``exec``: ``armplan
sim`` holds Ctrl-C so while it becomes ``python -m bridge.sim``, which
takes it once it can stop cleanly (:func:`shared.stop_signals.stop_on_signals`).
"""

from __future__ import annotations

import signal
from collections.abc import Iterator
from contextlib import contextmanager


class Held:
    """What a hold saw (a plain class: ``dataclasses`` takes 9 ms to import).

    Attributes:
        came: A Ctrl-C arrived while it was held (it is taken: never raised).
    """

    def __init__(self) -> None:
        self.came = False


def hold_interrupt() -> bool:
    """Block SIGINT in this thread: from now on it waits, pending.

    Threads started while it is blocked keep it blocked; it stays blocked
    across ``exec``. Returns whether it was blocked already.
    """
    before = signal.pthread_sigmask(signal.SIG_BLOCK, [signal.SIGINT])
    return signal.SIGINT in before


def take_interrupt() -> bool:
    """Take a pending SIGINT, if one is held, and unblock it; True if one was."""
    came = signal.sigtimedwait([signal.SIGINT], 0) is not None
    signal.pthread_sigmask(signal.SIG_UNBLOCK, [signal.SIGINT])
    return came


@contextmanager
def held_interrupt() -> Iterator[Held]:
    """Hold Ctrl-C inside the block; ``Held.came`` says, after it, if one came.

    A SIGINT blocked before the block (by whoever started this process)
    is left so. One ignored (a script's ``cmd &``: its Ctrl-C is not for
    this command) is not held: held, it stayed pending and was taken as a
    Ctrl-C, so the script's Ctrl-C ended the command it had left running.
    """
    held = Held()
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        yield held
        return
    if hold_interrupt():
        yield held
        return
    try:
        yield held
    finally:
        held.came = take_interrupt()
