"""SIGTERM stops a command as Ctrl-C does, and is reported as itself.

``armplan demo`` shuts down every process it started on Ctrl-C
(``KeyboardInterrupt``); SIGTERM (``timeout``, systemd, ``docker stop``)
must do the same clean-up, so it raises :class:`Terminated`, a kind of
``KeyboardInterrupt``. The command then exits 143 ("terminated"), the code
a shell gives a process ended by SIGTERM, not Ctrl-C's 130.
"""

from __future__ import annotations

import signal

#: Exit codes: 128 + the signal's number.
INTERRUPTED_CODE = 128 + signal.SIGINT
TERMINATED_CODE = 128 + signal.SIGTERM


class Terminated(KeyboardInterrupt):
    """SIGTERM arrived: unwind as for Ctrl-C, then exit 143."""


def terminate_on_sigterm() -> None:
    """From now on SIGTERM raises :class:`Terminated` in the main thread."""

    def terminate(signum: int, frame: object) -> None:
        raise Terminated

    signal.signal(signal.SIGTERM, terminate)
