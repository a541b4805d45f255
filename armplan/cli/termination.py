"""SIGTERM stops a command as Ctrl-C does, and is reported as itself.

``armplan demo`` shuts down every process it started on Ctrl-C
(``KeyboardInterrupt``); SIGTERM (``timeout``, systemd, ``docker stop``)
must do the same clean-up, so it raises :class:`Terminated`, a kind of
``KeyboardInterrupt``. The command then exits 143 ("terminated"), the code
a shell gives a process ended by SIGTERM, not Ctrl-C's 130.

A signal's exception is raised in whatever code runs when it lands, and
some code turns it into another error: pydantic-core, for one, reports a
``KeyboardInterrupt`` raised inside a serializer as a
``PydanticSerializationError``. So the handlers also remember the signal,
and :func:`stopped_by` tells the command's caller which one ended the run,
whatever the exception became on its way out.
"""

from __future__ import annotations

import signal
from types import FrameType

#: Exit codes: 128 + the signal's number.
INTERRUPTED_CODE = 128 + signal.SIGINT
TERMINATED_CODE = 128 + signal.SIGTERM

_received: list[signal.Signals] = []


class Terminated(KeyboardInterrupt):
    """SIGTERM arrived: unwind as for Ctrl-C, then exit 143."""


def terminate_on_sigterm() -> None:
    """From now on SIGTERM raises :class:`Terminated` in the main thread.

    Ctrl-C still raises ``KeyboardInterrupt``; both signals are remembered.
    A signal the process was started with ignored stays ignored (``cmd &``
    in a script: the script's Ctrl-C is not meant for it).
    """

    def terminate(signum: int, frame: FrameType | None) -> None:
        _received.append(signal.SIGTERM)
        raise Terminated

    def interrupt(signum: int, frame: FrameType | None) -> None:
        _received.append(signal.SIGINT)
        raise KeyboardInterrupt

    for signum, handler in ((signal.SIGTERM, terminate), (signal.SIGINT, interrupt)):
        if signal.getsignal(signum) is not signal.SIG_IGN:  # kept, as inherited
            signal.signal(signum, handler)


def stopped_by() -> signal.Signals | None:
    """The first signal that told this process to stop, if one did."""
    return _received[0] if _received else None


def forget_signals() -> None:
    """Forget the signals received (for a process that runs commands again)."""
    _received.clear()
