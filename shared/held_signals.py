"""Hold the stop signals for a few steps that must all happen or none.

Inside :func:`held_signals` a stop signal (Ctrl-C, SIGTERM, SIGHUP) is only
noted; once the steps are done the handlers that were there are put back
and the first signal noted is raised again, so its handler (Ctrl-C's
``KeyboardInterrupt``, the CLI's ``Terminated``) runs after the steps, not
between two of them. Python runs signal handlers in the main thread only,
whichever thread the signal was delivered to (blocking it with
``pthread_sigmask`` in one thread let another thread take it), so the
handlers are swapped there; elsewhere the block runs as it is.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from types import FrameType
from typing import Any

#: A signal's handler as ``signal.getsignal`` gives it (``None`` excepted).
Handler = Callable[[int, FrameType | None], Any] | int

#: The signals that stop a command: Ctrl-C, ``kill``/``timeout``, a closed terminal.
STOPS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


@contextmanager
def held_signals(signums: tuple[signal.Signals, ...] = STOPS) -> Iterator[None]:
    """Note ``signums`` inside the block; raise the first noted after it.

    A signal ignored (``SIG_IGN``) or handled outside Python is left so.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    came: list[int] = []

    def note(signum: int, _frame: FrameType | None) -> None:
        came.append(signum)  # no lock: a handler may interrupt its own thread

    before = {signum: signal.getsignal(signum) for signum in signums}
    held = {s: h for s, h in before.items() if h not in (None, signal.SIG_IGN)}
    try:
        for signum in held:
            signal.signal(signum, note)
        yield
    finally:
        stop = put_back(held)
        if came:
            signal.raise_signal(came[0])
        if stop is not None:
            raise stop


def put_back(handlers: Mapping[signal.Signals, Handler]) -> KeyboardInterrupt | None:
    """Set each signal's handler of ``handlers``, whatever signal comes meanwhile.

    ``signal.signal`` first runs the handlers of the signals that came: one
    set already could raise there (Ctrl-C's ``KeyboardInterrupt``), leaving
    the next ones unset, a SIGTERM noted by nobody ever after. That stop is
    kept, the setting goes on, and it is returned (to raise), or ``None``.
    """
    stop: KeyboardInterrupt | None = None
    for signum, handler in handlers.items():
        while True:
            try:
                signal.signal(signum, handler)
                break
            except KeyboardInterrupt as came:  # a handler set before raised
                stop = stop or came
    return stop
