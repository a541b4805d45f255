"""A bridge started with a frame rate no request could name is refused at start.

``--rate 0`` (or -5, 0.5, nan) used to start; every request that named no
rate then failed as ``internal_error``. Real processes; no router or robot
is needed, since the rate is checked before either is reached.
"""

from __future__ import annotations

import subprocess
import sys

import pytest

from armplan.launch import free_endpoint


def _run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", *args],
        capture_output=True,
        text=True,
        timeout=60,
        stdin=subprocess.DEVNULL,
    )


@pytest.mark.parametrize("rate", ["0", "-5", "0.5", "nan", "2000"])
def test_the_bridge_service_refuses_a_bad_rate(rate: str) -> None:
    """``python -m bridge.serve --rate R``: exit 1, the option and the range."""
    done = _run(
        "bridge.serve", "--rate", rate, "--connect", free_endpoint(), "--wait", "1"
    )
    assert done.returncode == 1, done.stderr
    assert (
        f"--rate must be a frame rate of 1..1000 Hz, got {float(rate)}" in done.stderr
    )
    assert "router" not in done.stderr  # refused before waiting for one


def test_the_line_bridge_refuses_a_bad_rate() -> None:
    """``python -m bridge --rate 0``: a usage error (exit 2) naming the option."""
    done = _run("bridge", "--rate", "0")
    assert done.returncode == 2
    assert done.stderr.endswith(
        "error: --rate must be a frame rate of 1..1000 Hz, got 0.0\n"
    )
