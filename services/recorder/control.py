"""Start and stop a recorder from another program (``armplan demo`` records so).

Two ways, the same recording:

- as its own process (what ``armplan demo`` should use, like every other
  armplan process)::

      with RecorderProcess.start(config, out / "session.mcap") as recorder:
          ...  # run the session; everything published is recorded
      recorder.paths  # the files, closed with their summaries

- in-process, on a bus the caller already has: ``Recorder(bus, options)``
  from ``services.recorder.service`` (``start()`` / ``stop()``).

:meth:`RecorderProcess.start` returns once the recorder has subscribed (it
waits for the ready line the process prints), so nothing published after it
returns is missed. :meth:`RecorderProcess.stop` sends SIGTERM and waits for
the file to be closed; a recorder that does not exit in time is killed, and
its file is still readable up to its last flush (read it with ``recover``).
"""

from __future__ import annotations

import contextlib
import os
import queue
import signal
import subprocess
import sys
import threading
from collections.abc import Sequence
from pathlib import Path
from typing import IO

from services.recorder.main import READY_PREFIX
from services.recorder.options import RecorderOptions
from shared.bus import BusConfig
from shared.bus.lifeline import PARENT_ENV
from shared.errors import RecordingError
from shared.lifecycle import Closes
from shared.recording.rotation import part_path

#: Longest wait for the recorder to be ready, and to exit after SIGTERM [s].
START_TIMEOUT = 30.0
STOP_TIMEOUT = 15.0


def recorder_command(config: BusConfig, options: RecorderOptions) -> list[str]:
    """The command line that runs a recorder with ``options`` on ``config``'s bus."""
    command = [sys.executable, "-m", "services.recorder", "-o", str(options.output)]
    if config.file is not None:
        command += ["--config", config.file]
    for endpoint in config.endpoints:
        command += ["--connect", endpoint]
    command += ["--namespace", config.namespace]
    command += ["--keys", *options.keys, "--flush-every", str(options.flush_every)]
    if options.rotation.max_bytes is not None:
        command += ["--rotate-size", str(options.rotation.max_bytes)]
    if options.rotation.max_seconds is not None:
        command += ["--rotate-duration", str(options.rotation.max_seconds)]
    if not options.foxglove:
        command.append("--no-foxglove")
    if options.overwrite:
        command.append("--overwrite")
    return command


class RecorderProcess(Closes):
    """A recorder running as its own process.

    Attributes:
        process: The OS process.
        options: What it records and where.
    """

    def __init__(self, process: subprocess.Popen[str], options: RecorderOptions):
        self.process = process
        self.options = options

    @classmethod
    def start(
        cls,
        config: BusConfig,
        output: str | Path,
        *,
        keys: Sequence[str] | None = None,
        options: RecorderOptions | None = None,
        log: IO[str] | int | None = None,
        timeout: float = START_TIMEOUT,
    ) -> RecorderProcess:
        """Start ``python -m services.recorder`` and wait until it records.

        Args:
            config: The bus (router endpoints, namespace, config file).
            output: The MCAP file.
            keys: Key expressions to record (default: every registered topic).
            options: Other settings (rotation, flush period); ``output`` and
                ``keys`` replace theirs.
            log: Where its stderr goes (a file, ``subprocess.DEVNULL``,
                ``None`` for this process's stderr).
            timeout: Longest wait for it to be ready [s].

        Raises:
            RecordingError: if it exits or is not ready in time (it is killed).
            Any exception raised while waiting (``KeyboardInterrupt``): it is
            killed first.
        """
        base = options or RecorderOptions()
        options = RecorderOptions(
            output=Path(output),
            keys=tuple(keys) if keys is not None else base.keys,
            rotation=base.rotation,
            flush_every=base.flush_every,
            foxglove=base.foxglove,
            planned_prefix=base.planned_prefix,
            executed_prefix=base.executed_prefix,
            overwrite=base.overwrite,
        )
        process = subprocess.Popen(
            recorder_command(config, options),
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=log,
            text=True,
            env={**os.environ, PARENT_ENV: str(os.getpid()), "PYTHONUNBUFFERED": "1"},
            start_new_session=True,
        )
        recorder = cls(process, options)
        try:
            recorder._wait_ready(timeout)
        except BaseException:  # Ctrl-C, SIGTERM: no caller would ever stop it
            recorder.kill()
            raise
        return recorder

    def _wait_ready(self, timeout: float) -> None:
        lines: queue.Queue[str] = queue.Queue()
        stdout = self.process.stdout
        assert stdout is not None
        threading.Thread(
            target=_pump, args=(stdout, lines), name="recorder-stdout", daemon=True
        ).start()
        try:
            line = lines.get(timeout=timeout)
        except queue.Empty:
            line = ""
        if not line.startswith(READY_PREFIX):
            self.kill()
            code = self.process.returncode
            raise RecordingError(
                f"the recorder for {self.options.output} did not start "
                f"(exit code {code}; see its log)",
                path=str(self.options.output),
            )

    @property
    def pid(self) -> int:
        """The process ID."""
        return self.process.pid

    @property
    def paths(self) -> list[Path]:
        """The files it has written so far, in order."""
        output = self.options.output
        if not self.options.rotation.rotates:
            return [output] if output.exists() else []
        found, number = [], 1
        while (path := part_path(output, number)).exists():
            found.append(path)
            number += 1
        return found

    def stop(self, timeout: float = STOP_TIMEOUT) -> list[Path]:
        """SIGTERM, wait for the files to be closed; the files written.

        Raises:
            RecordingError: if it had to be killed (its files are readable up
                to the last flush, with ``recover``).
        """
        self._signal(signal.SIGTERM)
        try:
            self.process.wait(timeout)
        except subprocess.TimeoutExpired:
            self.kill()
            raise RecordingError(
                f"the recorder did not stop within {timeout:.0f} s and was killed; "
                f"{self.options.output} is readable up to its last flush "
                "(armplan inspect --recover)",
                path=str(self.options.output),
            ) from None
        return self.paths

    def kill(self) -> None:
        """SIGKILL (the files keep what was flushed) and reap it."""
        self._signal(signal.SIGKILL)
        with contextlib.suppress(subprocess.TimeoutExpired):
            self.process.wait(STOP_TIMEOUT)

    def _signal(self, signum: int) -> None:
        if self.process.poll() is None:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(self.process.pid, signum)

    def close(self) -> None:
        """Stop the recorder (what leaving the ``with`` does)."""
        self.stop()


def _pump(stream: IO[str], lines: queue.Queue[str]) -> None:
    """Copy ``stream``'s lines into ``lines`` until it closes."""
    for line in stream:
        lines.put(line.rstrip("\n"))
    lines.put("")
