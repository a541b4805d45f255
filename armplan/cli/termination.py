"""SIGTERM and SIGHUP stop a command as Ctrl-C does, and are reported as themselves.

Every command (:func:`stops_unwinding`, from ``armplan.cli.main``) cleans
up on Ctrl-C (``KeyboardInterrupt``): ``armplan demo`` shuts down every
process it started, an experiment or the bench leaves no partial files.
SIGTERM (``timeout``, systemd, ``docker stop``) must do the same clean-up,
so it raises :class:`Terminated`, a kind of ``KeyboardInterrupt`` (it
killed the bench and the experiments outright, their partial files left).
The command then exits 143 ("terminated"), the code a shell gives a
process ended by SIGTERM, not Ctrl-C's 130. SIGHUP (the
terminal closed, an ssh session dropped) raises :class:`HungUp`, and the
command exits 129 ("hung up"); its default would have killed the demo
with every process it started still running until they noticed.

A signal's exception is raised in whatever code runs when it lands, and
some code turns it into another error: pydantic-core, for one, reports a
``KeyboardInterrupt`` raised inside a serializer as a
``PydanticSerializationError``. So the handlers also remember the signal,
and :func:`stopped_by` tells the command's caller which one ended the run,
whatever the exception became on its way out. Some code swallows it
outright (a finalizer, a weakref callback): inside :func:`stops_unwinding`
it is delivered again (:mod:`armplan.cli.swallowed_stops`).
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType

from armplan.cli.swallowed_stops import SwallowedStops

#: Exit codes: 128 + the signal's number.
INTERRUPTED_CODE = 128 + signal.SIGINT
TERMINATED_CODE = 128 + signal.SIGTERM
HUNG_UP_CODE = 128 + signal.SIGHUP

_received: list[signal.Signals] = []


class Terminated(KeyboardInterrupt):
    """SIGTERM arrived: unwind as for Ctrl-C, then exit 143."""


class HungUp(KeyboardInterrupt):
    """SIGHUP arrived (the terminal closed): unwind as for Ctrl-C, then exit 129."""


#: What each signal raises in the main thread.
_RAISES: dict[signal.Signals, type[KeyboardInterrupt]] = {
    signal.SIGTERM: Terminated,
    signal.SIGINT: KeyboardInterrupt,
    signal.SIGHUP: HungUp,
}


def terminate_on_sigterm() -> None:
    """From now on SIGTERM raises :class:`Terminated`, SIGHUP :class:`HungUp`.

    Both in the main thread. Ctrl-C still raises ``KeyboardInterrupt``;
    every signal is remembered. A signal the process was started with
    ignored stays ignored (``cmd &`` in a script: the script's Ctrl-C is
    not meant for it; ``nohup``: nor is the hangup).
    """

    def stop(signum: int, frame: FrameType | None) -> None:
        received = signal.Signals(signum)
        _received.append(received)
        raise _RAISES[received]

    for signum in _RAISES:
        if signal.getsignal(signum) is not signal.SIG_IGN:  # kept, as inherited
            signal.signal(signum, stop)


@contextmanager
def stops_unwinding() -> Iterator[None]:
    """:func:`terminate_on_sigterm` inside the block (in the main thread).

    The handlers there before are put back after it, each, even when a
    signal comes meanwhile (its exception is raised once all are back): a
    command run in a test's process leaves the test runner's own. Elsewhere
    than in the main thread (which alone may set handlers) the block runs as
    it is.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    from shared.held_signals import put_back  # loads libqi: not at import

    before = {signum: signal.getsignal(signum) for signum in _RAISES}
    swallowed = SwallowedStops({raised: signum for signum, raised in _RAISES.items()})
    forget_signals()  # an earlier command's, in this process
    try:
        swallowed.install()
        terminate_on_sigterm()
        yield
    finally:
        came = swallowed.release()
        # None: set outside Python, not restorable
        stop = put_back({s: h for s, h in before.items() if h is not None}) or came
        if stop is not None:
            raise stop


def signal_of(stop: KeyboardInterrupt) -> signal.Signals:
    """The signal a ``KeyboardInterrupt`` (or its kinds here) stands for.

    A start it interrupted (``StartInterrupted``, ``armplan up``) says which.
    """
    from shared.stop_signals import StartInterrupted  # loads libqi: not at import

    if isinstance(stop, Terminated):
        return signal.SIGTERM
    if isinstance(stop, StartInterrupted) and stop.signal is not None:
        return stop.signal
    return signal.SIGHUP if isinstance(stop, HungUp) else signal.SIGINT


def stopped_by() -> signal.Signals | None:
    """The first signal that told this process to stop, if one did."""
    return _received[0] if _received else None


def forget_signals() -> None:
    """Forget the signals received (for a process that runs commands again)."""
    _received.clear()
