"""A stop signal while ``armplan sim`` starts: one line and its exit code.

Run as a real process, Ctrl-C, SIGTERM or SIGHUP is sent at two points
of its start: while
``armplan`` loads its commands (libqi is mapped, pinocchio not yet), and
once it has become ``python -m bridge.sim`` (same process, new command
line), which then loads libqi and pinocchio again. Each printed a
traceback before.
"""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pytest


def _wait_for(seen: Callable[[], bool], timeout: float = 30.0) -> None:
    """Poll ``seen`` every 2 ms until it is true (``timeout`` [s])."""
    deadline = time.monotonic() + timeout
    while not seen():
        assert time.monotonic() < deadline, "the start never got there"
        time.sleep(0.002)


def _loading(pid: int) -> Callable[[], bool]:
    """``armplan`` has mapped libqi: it is loading its commands."""
    return lambda: "qi_python" in Path(f"/proc/{pid}/maps").read_text()


def _became_the_sim(pid: int) -> Callable[[], bool]:
    """``armplan sim`` has become ``python -m bridge.sim`` (its exec is done)."""
    return lambda: b"bridge.sim" in Path(f"/proc/{pid}/cmdline").read_bytes()


@pytest.mark.parametrize(
    ("signum", "code", "said"),
    [
        (signal.SIGINT, 130, "interrupted"),
        (signal.SIGTERM, 143, "terminated"),
        (signal.SIGHUP, 129, "hung up"),
    ],
    ids=["ctrl-c", "sigterm", "sighup"],
)
@pytest.mark.parametrize("point", [_loading, _became_the_sim])
def test_a_stop_signal_while_the_sim_starts_is_one_line_and_its_code(
    point: Callable[[int], Callable[[], bool]],
    signum: signal.Signals,
    code: int,
    said: str,
) -> None:
    """That signal at that point: ``armplan: <said>``, its exit code, nothing
    served. (SIGTERM and SIGHUP killed it there with no word: -15, -1.)"""
    sim = subprocess.Popen(
        [sys.executable, "-m", "armplan", "sim", "--listen", "tcp://127.0.0.1:0"],
        stdin=subprocess.DEVNULL,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        _wait_for(point(sim.pid))
        sim.send_signal(signum)
        out, err = sim.communicate(timeout=60)
    finally:
        sim.kill()
        sim.wait()
    assert (sim.returncode, err, out) == (code, f"armplan: {said}\n", "")
