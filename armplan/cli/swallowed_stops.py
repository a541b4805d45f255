"""A stop signal swallowed by a finalizer is delivered again.

A signal's handler raises its exception in whatever code runs when the
signal lands. In a finalizer (``__del__``) or a weakref callback (importlib's
module locks have one, run at every import) Python cannot raise it: it
prints "Exception ignored in ..." and goes on. A SIGHUP that landed there
let an experiment run to its end. :class:`SwallowedStops` hooks those
exceptions (``sys.unraisablehook``): a ``KeyboardInterrupt`` (Ctrl-C's, or
the CLI's ``Terminated`` and ``HungUp``) is not printed but its signal is
simulated again in the main thread, whose handler raises it in the code
that runs next. Any other exception goes to the hook that was there.
"""

from __future__ import annotations

import _thread
import signal
import sys
import threading
import time
from collections.abc import Mapping
from types import CodeType
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from sys import UnraisableHookArgs

#: How often a delivery looks whether the main thread has left the hook [s].
POLL = 0.001


class SwallowedStops:
    """Deliver again the stops swallowed while installed (main thread only).

    ``signals`` names the signal each exception type stands for (a
    ``KeyboardInterrupt`` of another type is Ctrl-C's).
    """

    def __init__(
        self, signals: Mapping[type[KeyboardInterrupt], signal.Signals]
    ) -> None:
        self._signals = dict(signals)
        self._before = sys.unraisablehook
        self._lock = threading.Lock()
        self._ended = False

    def install(self) -> None:
        """Take over ``sys.unraisablehook``."""
        self._before = sys.unraisablehook
        sys.unraisablehook = self._hook

    def release(self) -> KeyboardInterrupt | None:
        """Put the hook back; no delivery is made after this.

        A delivery already made may raise its stop here: it is returned (to
        raise once the caller has put its own things back), or ``None``.
        """
        try:
            with self._lock:
                self._ended = True
            sys.unraisablehook = self._before
        except KeyboardInterrupt as stop:
            sys.unraisablehook = self._before
            return stop
        return None

    def _hook(self, unraisable: UnraisableHookArgs) -> None:
        stop = unraisable.exc_value
        if not isinstance(stop, KeyboardInterrupt):
            self._before(unraisable)
            return
        signum = self._signals.get(type(stop), signal.SIGINT)
        code = SwallowedStops._hook.__code__
        threading.Thread(
            target=self._deliver, args=(code, signum), name="armplan-stop", daemon=True
        ).start()

    def _deliver(self, hook: CodeType, signum: signal.Signals) -> None:
        """Simulate ``signum`` in the main thread once it has left ``hook``.

        Simulated from the hook itself, the handler would run (and raise)
        inside the hook, where its exception is swallowed again.
        """
        while _main_runs(hook):
            time.sleep(POLL)
        with self._lock:
            if not self._ended:
                _thread.interrupt_main(signum)


def _main_runs(code: CodeType) -> bool:
    """Whether the main thread is inside a call of ``code``."""
    frame = sys._current_frames().get(threading.main_thread().ident or 0)
    while frame is not None and frame.f_code is not code:
        frame = frame.f_back
    return frame is not None
