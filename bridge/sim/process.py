"""Start and stop the simulated NAO as a separate process.

The child runs ``python -m bridge.sim`` and prints ``armplan-sim ready URL``
once ALMotion is served; :meth:`SimProcess.start` waits for that line (with
a timeout) and keeps reading the child's output on a thread so that the
child never blocks on a full pipe. The child's stdin is a pipe from this
process: if this process ends in any way (even killed), the pipe closes and
the child stops by itself, so no simulated NAO outlives its parent.
"""

from __future__ import annotations

import os
import queue
import subprocess
import sys
import threading
from collections import deque
from pathlib import Path

from shared.lifecycle import StartStop

#: The line the simulated NAO prints when it serves ALMotion.
READY = "armplan-sim ready"


class SimProcess(StartStop):
    """A simulated NAO process.

    Use as a context manager, or call :meth:`start` and then :meth:`stop`
    (or :meth:`kill`) yourself.

    Attributes:
        url: Where its ALMotion is served, known once started.
    """

    def __init__(
        self,
        listen: str = "tcp://127.0.0.1:0",
        log_path: str | Path | None = None,
        period: float = 0.02,
        startup_timeout: float = 30.0,
        killed_calls_return: bool = False,
        limp_sag: float = 0.0,
        grip: float | None = None,
    ) -> None:
        """Describe the process; nothing starts yet.

        Args:
            listen: NAOqi address to serve at; port 0 picks a free one.
            log_path: The sim's JSON-lines log file, or None.
            period: Control cycle [s].
            startup_timeout: Longest wait for the ready line [s].
            killed_calls_return: A blocking call whose motion task is killed
                returns normally instead of raising (``--killed-calls-return``).
            limp_sag: How long a joint let go falls [s] (``--limp-sag``).
            grip: Each hand holds an object this wide (open fraction,
                ``--grip``); None: nothing in the hands.
        """
        self.listen = listen
        self.log_path = None if log_path is None else Path(log_path)
        self.period = period
        self.startup_timeout = startup_timeout
        self.killed_calls_return = killed_calls_return
        self.limp_sag = limp_sag
        self.grip = grip
        self.url = ""
        self.output: deque[str] = deque(maxlen=200)
        self._process: subprocess.Popen[str] | None = None
        self._ready: queue.Queue[str] = queue.Queue()

    def command(self) -> list[str]:
        """The child's command line."""
        cmd = [sys.executable, "-m", "bridge.sim", "--listen", self.listen]
        cmd += ["--period", str(self.period), "--stop-on-stdin-eof"]
        if self.killed_calls_return:
            cmd.append("--killed-calls-return")
        if self.limp_sag:
            cmd += ["--limp-sag", str(self.limp_sag)]
        if self.grip is not None:
            cmd += ["--grip", str(self.grip)]
        if self.log_path is not None:
            cmd += ["--log", str(self.log_path)]
        return cmd

    @property
    def pid(self) -> int:
        """The child's process id (0 if not started)."""
        return 0 if self._process is None else self._process.pid

    def start(self) -> str:
        """Start the child and wait until it serves; returns its URL.

        Raises:
            RuntimeError: if it exits or is not ready within the timeout
                (the child is ended first).
        """
        env = dict(os.environ, PYTHONUNBUFFERED="1")
        self._process = subprocess.Popen(
            self.command(),
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            stdin=subprocess.PIPE,
            text=True,
            env=env,
        )
        threading.Thread(target=self._drain, daemon=True, name="sim-output").start()
        try:
            line = self._ready.get(timeout=self.startup_timeout)
        except queue.Empty:
            self.kill()
            raise RuntimeError(
                f"simulated NAO not ready in {self.startup_timeout} s: "
                + " | ".join(self.output)
            ) from None
        if not line:
            self.stop()
            raise RuntimeError("simulated NAO exited: " + " | ".join(self.output))
        self.url = line.split()[-1]
        return self.url

    def _drain(self) -> None:
        assert self._process is not None and self._process.stdout is not None
        for line in self._process.stdout:
            self.output.append(line.rstrip())
            if line.startswith(READY):
                self._ready.put(line.strip())
        self._ready.put("")

    def running(self) -> bool:
        """True while the child runs."""
        return self._process is not None and self._process.poll() is None

    def exit_code(self) -> int | None:
        """The child's exit code once it has exited, else ``None``."""
        return None if self._process is None else self._process.poll()

    def stop(self, timeout: float = 5.0) -> int | None:
        """Ask the child to stop (SIGTERM), kill it after ``timeout`` [s]."""
        if self._process is None:
            return None
        if self._process.poll() is None:
            self._process.terminate()
            try:
                return self._process.wait(timeout)
            except subprocess.TimeoutExpired:
                pass
        return self.kill()

    def kill(self, timeout: float = 5.0) -> int | None:
        """End the child at once (SIGKILL), as a crash or a pulled cable would."""
        if self._process is None:
            return None
        if self._process.poll() is None:
            self._process.kill()
        return self._process.wait(timeout)
