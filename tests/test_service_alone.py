"""One process per service and namespace (``shared/bus/service_alone.py``).

Real router and service processes on a free loopback port.
"""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from armplan.launch import Launcher, free_endpoint
from armplan.launch.child import Child
from services.recorder import RecorderProcess
from shared.bus import Bus, BusConfig, load_config, open_router

#: Longest wait for a service process to give up [s].
EXIT_TIMEOUT = 60.0


def test_a_second_service_in_the_namespace_refuses_to_start() -> None:
    """A second ``python -m services.timing`` on the router of ``armplan up``
    (or on a router linked to it) served beside the first: two planners
    published one ``armplan plan`` three times for a following robot. It
    now exits 1 naming the held token, and the first serves on."""
    config = load_config(None, (free_endpoint(),))
    with Launcher(config, ["timing"]) as stack:
        command = [sys.executable, "-m", "services.timing", "--wait", "10"]
        second = subprocess.run(
            [*command, "--connect", config.endpoints[0]],
            capture_output=True,
            text=True,
            timeout=EXIT_TIMEOUT,
            check=False,
        )
        assert second.returncode == 1, second.stderr
        assert (
            "service timing: service 'timing' is already running "
            "(armplan/alive/timing is held by another process): two timing "
            "services in one namespace would each answer every request"
        ) in second.stderr
        assert "planner" not in second.stderr  # it spoke of planners for all
        assert stack.exited() == []
        with Bus.connect(config) as bus:
            assert "timing" in bus.alive()


def test_a_killed_service_started_again_at_once_is_not_refused(
    capfd: pytest.CaptureFixture[str],
) -> None:
    """``armplan faults`` SIGKILLs a service and starts it again at once: the
    router drops the dead one's token when its connection closes (about
    20 ms on loopback), long before the new process has started and asks,
    so the new one serves.

    The test waits for the new process to say it serves, not for a token:
    on a loaded machine (three test workers on two CPUs) the dead one's
    token lingered long enough to satisfy ``wait_alive``, and the check a
    second later fell between it and the new one's."""
    config = load_config(None, (free_endpoint(),))
    with Launcher(config, ["timing"]) as stack:
        killed = stack.services["timing"]
        killed.signal(signal.SIGKILL)
        killed.process.wait(EXIT_TIMEOUT)
        again = stack.start_service("timing")
        ready = f"armplan.bus[{again.pid}] INFO service timing ready"
        said = _wait_said(capfd, ready, again, EXIT_TIMEOUT)
        assert ready in said, said[-2000:]
        with Bus.connect(config) as bus:
            # it is the new one that holds the token, and it stays
            time.sleep(1.0)
            assert again.process.poll() is None
            assert "timing" in bus.alive()


def _wait_said(
    capfd: pytest.CaptureFixture[str], line: str, child: Child, timeout: float
) -> str:
    """The standard error captured until ``line`` appears, ``child`` exits or
    ``timeout`` [s] passes."""
    said = ""
    deadline = time.monotonic() + timeout
    while line not in said and child.process.poll() is None:
        if time.monotonic() > deadline:
            break
        time.sleep(0.05)
        said += capfd.readouterr().err
    return said + capfd.readouterr().err


def test_recorders_run_side_by_side_in_one_namespace(tmp_path: Path) -> None:
    """The recorder answers no request and publishes nothing: a second one
    (on machine B beside A's, each into its own file) is no duplicate
    answer, so it does not go through ``check_alone``."""
    config = BusConfig(endpoints=(free_endpoint(),))
    with (
        open_router(config),
        RecorderProcess.start(config, tmp_path / "a.mcap") as first,
        RecorderProcess.start(config, tmp_path / "b.mcap") as second,
    ):
        assert first.process.poll() is None
        assert second.process.poll() is None
