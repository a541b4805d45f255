"""Run the ``armplan`` command line as a real process, for the tests."""

from __future__ import annotations

import subprocess
import sys

from hang_report import hang_report

#: Longest a command may run [s].
TIMEOUT = 60.0


def armplan(*args: str) -> subprocess.CompletedProcess[str]:
    """``python -m armplan ARGS``: its exit code, stdout and stderr.

    Raises:
        AssertionError: it ran over :data:`TIMEOUT`; the message says what
            it and its children were doing (:func:`hang_report`, taken
            before the kill) and what it wrote on stderr.
    """
    process = subprocess.Popen(
        [sys.executable, "-m", "armplan", *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        stdout, stderr = process.communicate(timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        report = hang_report(process.pid)
        process.kill()
        _, stderr = process.communicate()
        raise AssertionError(
            f"armplan {' '.join(args)} did not exit within {TIMEOUT} s\n{report}\n"
            f"--- its stderr (tail) ---\n{stderr[-3000:]}"
        ) from None
    return subprocess.CompletedProcess(process.args, process.returncode, stdout, stderr)
