"""Run the ``armplan`` command line as a real process, for the tests."""

from __future__ import annotations

import subprocess
import sys


def armplan(*args: str) -> subprocess.CompletedProcess[str]:
    """``python -m armplan ARGS``: its exit code, stdout and stderr (60 s at most)."""
    return subprocess.run(
        [sys.executable, "-m", "armplan", *args],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
