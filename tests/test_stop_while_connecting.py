"""A process still waiting for its router stops when asked to.

A demo killed during its start-up leaves its services, recorder and bridge
waiting for a router that is gone (``--wait`` seconds); their parent's death sends
them SIGTERM. They used to act on it only once the wait was over (~12 s of
orphans); now the wait watches the stop request and the process exits 0
at once.
"""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from armplan.launch import free_endpoint

#: The wait for a router that never comes [s]: far beyond STOP_TIMEOUT.
WAIT = 300.0
#: Longest a process may take to exit after SIGTERM (a loaded machine) [s].
STOP_TIMEOUT = 30.0
#: Longest a process may take to install its SIGTERM handler [s].
START_TIMEOUT = 60.0


def catches_sigterm(pid: int) -> bool:
    """Whether process ``pid`` has its own SIGTERM handler (``SigCgt``)."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("SigCgt:"):
            return bool(int(line.split()[1], 16) >> (signal.SIGTERM - 1) & 1)
    return False


def wait_for_handler(process: subprocess.Popen[str]) -> None:
    deadline = time.monotonic() + START_TIMEOUT
    while not catches_sigterm(process.pid):
        assert process.poll() is None, process.communicate()
        assert time.monotonic() < deadline, "no SIGTERM handler installed"
        time.sleep(0.05)


@pytest.mark.parametrize("module", ["services.ik", "services.recorder", "bridge.serve"])
def test_sigterm_ends_the_wait_for_the_router(module: str, tmp_path: Path) -> None:
    """No router answers: SIGTERM ends the process with exit code 0, and it
    says it was asked to stop, not that the router is missing."""
    command = [sys.executable, "-m", module, "--connect", free_endpoint()]
    command += ["--wait", str(WAIT)]
    if module == "services.recorder":
        command += ["-o", str(tmp_path / "never.mcap")]
    process = subprocess.Popen(
        command,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        wait_for_handler(process)
        process.send_signal(signal.SIGTERM)
        _, stderr = process.communicate(timeout=STOP_TIMEOUT)
    finally:
        if process.poll() is None:
            process.kill()
            process.communicate()
    assert process.returncode == 0, stderr
    assert "asked to stop before a router answered" in stderr
    assert "ERROR" not in stderr
