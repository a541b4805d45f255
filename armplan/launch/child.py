"""One child process of the launcher, in its own process group.

Its own group lets the launcher stop the child and anything it started with
one signal, and keeps a terminal's Ctrl-C for the launcher, which then stops
the children in order. ``ARMPLAN_PARENT_PID`` makes the child end itself if
the launcher dies (see ``shared/bus/lifeline.py``).
"""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import time
from collections.abc import Sequence
from typing import IO

from shared.bus.lifeline import PARENT_ENV

#: Pause between checks while waiting for children to exit [s].
POLL = 0.05
#: Longest wait for a killed child to be reaped [s].
REAP_TIMEOUT = 5.0


class Child:
    """A started child process.

    Attributes:
        name: What it is, e.g. ``"router"`` or ``"ik"``.
        process: The process.
    """

    def __init__(self, name: str, process: subprocess.Popen[bytes]) -> None:
        self.name = name
        self.process = process

    @classmethod
    def start(
        cls, name: str, module: str, args: Sequence[str], log: IO[str] | int | None
    ) -> Child:
        """Run ``python -m module args`` with its output going to ``log``.

        Args:
            name: What it is (for messages).
            module: The module to run.
            args: Its arguments.
            log: Where its stdout and stderr go: a file, ``subprocess.DEVNULL``,
                or ``None`` for the launcher's stderr.
        """
        env = {**os.environ, PARENT_ENV: str(os.getpid()), "PYTHONUNBUFFERED": "1"}
        out = log if log is not None else sys.stderr
        process = subprocess.Popen(
            [sys.executable, "-m", module, *args],
            stdin=subprocess.DEVNULL,
            stdout=out,
            stderr=out,
            env=env,
            start_new_session=True,
        )
        return cls(name, process)

    @property
    def pid(self) -> int:
        """The process ID."""
        return self.process.pid

    def exit_code(self) -> int | None:
        """The exit code if it has exited, else ``None``."""
        return self.process.poll()

    def signal(self, signum: int) -> None:
        """Send ``signum`` to the child's whole process group (if still there)."""
        if self.process.poll() is None:
            with contextlib.suppress(ProcessLookupError):  # exited meanwhile
                os.killpg(self.process.pid, signum)


def stop_all(children: Sequence[Child], grace: float) -> None:
    """SIGTERM every child's group, wait up to ``grace`` [s], then SIGKILL.

    Returns once every child has exited and been reaped (or, stuck in the
    kernel, ignored SIGKILL for ``REAP_TIMEOUT``).
    """
    for child in children:
        child.signal(signal.SIGTERM)
    deadline = time.monotonic() + grace
    while time.monotonic() < deadline and any(c.exit_code() is None for c in children):
        time.sleep(POLL)
    for child in children:
        child.signal(signal.SIGKILL)
        with contextlib.suppress(subprocess.TimeoutExpired):  # stuck in the kernel
            child.process.wait(REAP_TIMEOUT)
