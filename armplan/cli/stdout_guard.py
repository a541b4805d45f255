"""Telling a failed write to stdout from the command's other errors.

``armplan plan --json > /dev/full`` ended in an ``OSError`` traceback (no
space left on the device) and, with stdout closed (``>&-``: Python's
``sys.stdout`` is ``None``), in ``AttributeError: 'NoneType' object has no
attribute 'write'``. While a command runs, :func:`guarded_stdout` puts a
:class:`GuardedStdout` in ``sys.stdout``: a write or flush that fails
raises :class:`StdoutError`, an ``OSError`` (so that the progress lines'
``except OSError`` still catches it) that
:func:`armplan.cli.main.run_command` reports in one line. A reader that
left (``BrokenPipeError``) stays as it is: ``run_command`` ends such a run
quietly.
"""

from __future__ import annotations

import errno
import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any, TextIO


class StdoutError(OSError):
    """Writing the command's output to stdout failed (not a broken pipe)."""


class GuardedStdout:
    """``stream`` (``None``: stdout is closed); failed writes: :class:`StdoutError`."""

    def __init__(self, stream: TextIO | None) -> None:
        self._stream = stream

    def write(self, text: str) -> int:
        return int(self._call("write", text))

    def flush(self) -> None:
        self._call("flush")

    def _call(self, name: str, *args: Any) -> Any:
        if self._stream is None:
            raise StdoutError(errno.EBADF, "stdout is closed")
        try:
            return getattr(self._stream, name)(*args)
        except BrokenPipeError:
            raise
        except OSError as error:
            raise StdoutError(error.errno, error.strerror) from None

    def __getattr__(self, name: str) -> Any:
        if self._stream is None:
            raise StdoutError(errno.EBADF, "stdout is closed")
        return getattr(self._stream, name)


@contextmanager
def guarded_stdout() -> Iterator[None]:
    """Run the block with ``sys.stdout`` guarded, then put it back.

    With stdout closed, file descriptor 1 is first taken by ``/dev/null``,
    so that no file the command opens becomes a child process's stdout.
    """
    given = sys.stdout
    if given is None:
        _hold_descriptor_1()
    sys.stdout = GuardedStdout(given)
    try:
        yield
    finally:
        sys.stdout = given


def _hold_descriptor_1() -> None:
    try:
        os.fstat(1)
    except OSError:
        devnull = os.open(os.devnull, os.O_WRONLY)
        if devnull != 1:
            os.dup2(devnull, 1)
            os.close(devnull)


def discard_stdout() -> None:
    """Send what stdout still holds, and all later output, to ``/dev/null``.

    So that exit's flush of what could not be written fails no second time.
    """
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, 1)
    os.close(devnull)
