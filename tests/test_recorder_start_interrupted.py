"""A recorder interrupted while it starts is not left running.

``RecorderProcess.start`` starts the recorder in its own session (Ctrl-C
at the terminal does not reach it) and waits for its ready line. A signal
handled meanwhile in the caller (``armplan demo``'s Ctrl-C) used to leave
the wait with the recorder still running, ~10 s after the demo said it had
stopped everything. Here no router answers, so the recorder sits in its
start-up until the test's own signal interrupts the wait.
"""

from __future__ import annotations

import contextlib
import os
import signal
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from armplan.launch import free_endpoint
from services.recorder import RecorderProcess
from shared.bus import BusConfig

#: Longest wait for the recorder process to appear [s].
APPEAR_TIMEOUT = 30.0


class SignalledError(Exception):
    """Raised by the test's signal handler in the main thread."""


def recorder_children() -> list[int]:
    """PIDs of this process's children running ``services.recorder``."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        with contextlib.suppress(OSError):
            stat = (entry / "stat").read_text()
            parent = int(stat[stat.rindex(")") + 2 :].split()[1])
            command = (entry / "cmdline").read_bytes()
            if parent == os.getpid() and b"services.recorder" in command:
                found.append(int(entry.name))
    return found


@contextlib.contextmanager
def interrupt_once_started() -> Iterator[list[int]]:
    """SIGUSR1 to this process once a recorder child runs; yields its PIDs."""
    seen: list[int] = []

    def raise_interrupted(signum: int, frame: object) -> None:
        raise SignalledError

    def watch() -> None:
        deadline = time.monotonic() + APPEAR_TIMEOUT
        while not seen and time.monotonic() < deadline:
            seen.extend(recorder_children())
            time.sleep(0.05)
        os.kill(os.getpid(), signal.SIGUSR1)

    previous = signal.signal(signal.SIGUSR1, raise_interrupted)
    watcher = threading.Thread(target=watch, daemon=True)
    watcher.start()
    try:
        yield seen
    finally:
        watcher.join(APPEAR_TIMEOUT + 5)
        signal.signal(signal.SIGUSR1, previous)


def test_an_interrupted_start_kills_the_recorder(tmp_path: Path) -> None:
    """The interrupt propagates, and the recorder is gone when it does."""
    config = BusConfig(endpoints=(free_endpoint(),), namespace="interrupted")
    with interrupt_once_started() as seen, pytest.raises(SignalledError):
        RecorderProcess.start(config, tmp_path / "never.mcap")
    try:
        assert len(seen) == 1
        assert recorder_children() == []  # killed and reaped
    finally:
        for pid in recorder_children():
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
