"""A stop signal while a command loads is held, then reported in one line.

``armplan`` imports every command before it parses its arguments (about
0.7 s: libqi, pinocchio, pydantic, zenoh). A ``KeyboardInterrupt`` raised
in the middle of that printed a traceback, or came out of a C extension's
initialisation as an ``ImportError``; a SIGTERM or SIGHUP killed the
command with no word (exit -15, -1). So the three are blocked while the
commands load: one that arrives waits, pending, and is taken when the
loading ends, and the command exits 130 ("interrupted"), 143
("terminated") or 129 ("hung up") without running.

A blocked signal stays blocked, and pending, across ``exec``: ``armplan
sim`` holds them so while it becomes ``python -m bridge.sim``, which
takes them once it can stop cleanly (:func:`shared.stop_signals.stop_on_signals`).
"""

from __future__ import annotations

import signal
from collections.abc import Iterator
from contextlib import contextmanager

#: The signals held: Ctrl-C, SIGTERM and SIGHUP (they stop a command alike).
HELD_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


class Held:
    """What a hold saw (a plain class: ``dataclasses`` takes 9 ms to import).

    Attributes:
        signal: The first stop signal that arrived while it was held (it is
            taken: never raised), or None.
    """

    def __init__(self) -> None:
        self.signal: signal.Signals | None = None

    @property
    def came(self) -> bool:
        """A stop signal arrived while it was held."""
        return self.signal is not None


def hold_interrupt() -> frozenset[signal.Signals]:
    """Block SIGINT, SIGTERM and SIGHUP in this thread: from now on they wait.

    One ignored (``nohup``, a script's ``cmd &``) is left alone: it is not
    meant to stop the command. Threads started while they are blocked keep
    them blocked; they stay blocked across ``exec``.

    Returns:
        Those this call blocked (not blocked before, by whoever started this
        process): the ones to take and unblock (:func:`take_interrupt`).
    """
    held = [s for s in HELD_SIGNALS if signal.getsignal(s) is not signal.SIG_IGN]
    before = signal.pthread_sigmask(signal.SIG_BLOCK, held)
    return frozenset(signal.Signals(s) for s in held if s not in before)


def take_interrupt(held: frozenset[signal.Signals]) -> signal.Signals | None:
    """Take those of ``held`` pending, and unblock ``held``.

    Returns:
        The first of them (SIGINT, then SIGTERM, then SIGHUP, if several
        are pending), or None if none was.
    """
    came = None
    for signum in (s for s in HELD_SIGNALS if s in held):
        if signal.sigtimedwait([signum], 0) is not None and came is None:
            came = signal.Signals(signum)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, held)
    return came


@contextmanager
def held_interrupt() -> Iterator[Held]:
    """Hold the stop signals inside the block; ``Held.signal``: the one that came.

    Signals blocked before the block (by whoever started this process) are
    left so. An ignored one (a script's ``cmd &`` ignores Ctrl-C: the
    script's Ctrl-C is not for this command) is not held: held, it stayed
    pending and was taken as a Ctrl-C, so the script's Ctrl-C ended the
    command it had left running. The others are held all the same.
    """
    held = Held()
    blocked = hold_interrupt()
    try:
        yield held
    finally:
        held.signal = take_interrupt(blocked)
