"""Turn SIGTERM, SIGINT and SIGHUP into a stop request, without a lock in the handler.

A Python signal handler runs in the main thread, between two bytecodes of
whatever that thread was doing. A handler that calls ``threading.Event.set``
takes the event's internal lock; the main thread takes that same lock for a
moment on every pass of ``event.wait(timeout)``, the loop every armplan
process waits in. A signal that lands in that moment makes the handler wait
for a lock its own thread holds: the process hangs and ignores every later
Ctrl-C (a fresh-clone CI run saw ``armplan up`` hang so on SIGINT).

So the handler here only writes a byte to a pipe. One relay thread per
process reads the pipe and sets the events; it takes the lock from another
thread, which simply waits until the main thread lets go.

SIGHUP is the terminal going away (a closed window, a dropped ssh
session): left to its default it killed ``armplan record`` before the
recording got its summary, so it stops a process as Ctrl-C does. A process
started with SIGHUP ignored (``nohup armplan record ...``), or SIGINT
(``armplan record &`` in a script: the script's Ctrl-C is not for it), keeps
ignoring it: that is what it was asked to do, as the CLI's own handlers
(``armplan.cli.termination``) keep it. Example::

    stop = stop_on_signals()
    while not stop.wait(0.2):
        ...  # work until SIGTERM or Ctrl-C
"""

from __future__ import annotations

import contextlib
import os
import signal
import threading
import weakref
from collections.abc import Iterable
from types import FrameType

#: The signals that ask an armplan process to stop: SIGTERM, Ctrl-C, and
#: SIGHUP (its terminal closed).
STOP_SIGNALS = (signal.SIGTERM, signal.SIGINT, signal.SIGHUP)


class StopRequest(threading.Event):
    """An event set soon after a stop signal arrives, knowing which one.

    Attributes:
        signal: The first signal that set it; ``None`` until one did (also
            when code set it with :meth:`set`).
    """

    def __init__(self) -> None:
        super().__init__()
        self.signal: signal.Signals | None = None

    def request(self, signum: int) -> None:
        """Note ``signum`` (if it is the first) and set the event."""
        if self.signal is None:
            self.signal = signal.Signals(signum)
        self.set()


class StartInterrupted(KeyboardInterrupt):
    """A stop request arrived while processes were starting; they were stopped.

    A kind of ``KeyboardInterrupt``: the caller unwinds as for Ctrl-C, and
    ``armplan`` exits 130 ("interrupted"), or 143 ("terminated") if
    ``signal`` is SIGTERM.

    Attributes:
        signal: The signal that asked to stop, if one did.
    """

    def __init__(self, signum: signal.Signals | None) -> None:
        super().__init__(f"stopped by {signum.name if signum else 'a request'}")
        self.signal = signum


class _Relay:
    """A pipe the handler writes to, and the thread that sets the events.

    The handler writes the signal's number, so each event learns which
    signal set it. The events are held weakly: a process that asks for stop
    requests again and again (a command run in-process many times) keeps
    none it dropped.
    """

    def __init__(self) -> None:
        self.read_end, self.write_end = os.pipe()
        os.set_blocking(self.write_end, False)
        self.events: weakref.WeakSet[StopRequest] = weakref.WeakSet()
        threading.Thread(target=self._run, name="armplan-signals", daemon=True).start()

    def _run(self) -> None:
        while received := os.read(self.read_end, 64):
            for event in list(self.events):
                for signum in received:
                    event.request(signum)

    def handler(self, signum: int, frame: FrameType | None) -> None:
        """The signal handler: one byte into the pipe (no lock, no wait)."""
        with contextlib.suppress(BlockingIOError):  # full: a wake-up is pending
            os.write(self.write_end, bytes([signum]))


_relay: _Relay | None = None
_relay_lock = threading.Lock()


def _the_relay() -> _Relay:
    global _relay
    with _relay_lock:
        if _relay is None:
            _relay = _Relay()
        return _relay


def stop_on_signals(signals: Iterable[int] = STOP_SIGNALS) -> StopRequest:
    """An event set soon after any of ``signals`` arrives.

    Installs the handler for each signal (call it from the main thread, as
    :func:`signal.signal` requires). Every event made by this function is
    set by any of the signals installed, from then on. SIGHUP or SIGINT
    ignored at start (``nohup``; a script's ``cmd &``) stays ignored. One
    of ``signals`` blocked and pending when it is called (``armplan sim``
    holds Ctrl-C while it becomes ``python -m bridge.sim``) is taken: the
    request is set before this returns; each is unblocked (an ignored one
    too: held, it is dropped, not left blocked for the process's life).

    Args:
        signals: Signal numbers; default SIGTERM, SIGINT and SIGHUP.

    Returns:
        The stop request (a ``threading.Event``; ``signal`` names the signal).
    """
    relay = _the_relay()
    stop = StopRequest()
    relay.events.add(stop)
    installed = []
    for signum in signals:
        if signum != signal.SIGTERM and signal.getsignal(signum) is signal.SIG_IGN:
            # nohup, cmd &: that signal is not meant to stop it; one held
            # (armplan sim's exec) is dropped, not left blocked for good
            signal.pthread_sigmask(signal.SIG_UNBLOCK, [signum])
            continue
        signal.signal(signum, relay.handler)
        installed.append(signum)
    for signum in sorted(installed, key=_take_order):  # as armplan's own hold
        _take_held(signum, stop)
    return stop


def _take_order(signum: int) -> int:
    """Held signals pending together are taken Ctrl-C first, then SIGTERM."""
    order = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
    return order.index(signum) if signum in order else len(order)


def _take_held(signum: int, stop: StopRequest) -> None:
    """Set ``stop`` if ``signum`` is blocked and pending here; unblock it."""
    if signal.sigtimedwait([signum], 0) is not None:
        stop.request(signum)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, [signum])
