"""A command on a terminal of its own, which then closes (a dropped ssh session).

:class:`Terminal` starts a command as the leader of a new session whose
controlling terminal is a pseudo-terminal, with its stdin, stdout and
stderr on it. :meth:`Terminal.close` closes the terminal's other end, as a
closed window or a dropped ssh connection does: the kernel sends the
command SIGHUP, and its writes to the terminal fail from then on (EIO).
"""

from __future__ import annotations

import contextlib
import fcntl
import os
import pty
import select
import signal
import subprocess
import termios
import time
from collections.abc import Mapping, Sequence


class Terminal:
    """A command running on a pseudo-terminal that the test can close.

    Args:
        command: The program and its arguments.
        env: Its environment (default: this process's).
        ignore_hangup: Start it with SIGHUP ignored, as ``nohup`` does.

    Attributes:
        process: The command's process.
        output: What it wrote to the terminal so far.
    """

    def __init__(
        self,
        command: Sequence[str],
        env: Mapping[str, str] | None = None,
        ignore_hangup: bool = False,
    ) -> None:
        self._master, slave = pty.openpty()

        def take_terminal() -> None:  # in the child, before it runs the command
            os.setsid()
            fcntl.ioctl(0, termios.TIOCSCTTY, 0)
            if ignore_hangup:
                signal.signal(signal.SIGHUP, signal.SIG_IGN)

        self.process = subprocess.Popen(
            list(command),
            stdin=slave,
            stdout=slave,
            stderr=slave,
            env=None if env is None else dict(env),
            preexec_fn=take_terminal,
        )
        os.close(slave)
        self.output = ""
        self._open = True

    def wait_for(self, text: str, timeout: float) -> str:
        """The output once it holds ``text``.

        Raises:
            AssertionError: it did not come within ``timeout`` [s], or the
                command closed the terminal first.
        """
        deadline = time.monotonic() + timeout
        while text not in self.output:
            left = deadline - time.monotonic()
            assert left > 0, f"no {text!r} in {timeout} s: {self.output[-2000:]}"
            if not select.select([self._master], [], [], left)[0]:
                continue
            try:
                chunk = os.read(self._master, 4096)
            except OSError:  # EIO: no process has the terminal open any more
                chunk = b""
            assert chunk, f"the command left before {text!r}: {self.output[-2000:]}"
            self.output += chunk.decode(errors="replace")
        return self.output

    def close(self) -> None:
        """Close the terminal: the command gets SIGHUP; its output goes nowhere."""
        if self._open:
            self._open = False
            os.close(self._master)

    def kill(self) -> None:
        """Close the terminal and SIGKILL the command (cleanup)."""
        self.close()
        if self.process.poll() is None:
            with contextlib.suppress(ProcessLookupError):
                self.process.kill()
            self.process.wait(10)
