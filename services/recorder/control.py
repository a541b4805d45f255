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
A recorder that exits with an error, before the stop (the file system
refused a write: it stops at once) or during it, makes ``stop`` raise
:class:`~shared.errors.RecordingError` with the reason it printed: its
files then lack their summaries.
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
from dataclasses import replace
from pathlib import Path
from typing import IO

from services.recorder.main import FAILED_PREFIX, READY_PREFIX
from services.recorder.options import RecorderOptions
from services.recorder.sink import STOP_TIMEOUT as WRITE_OUT_TIMEOUT
from shared.bus import BusConfig
from shared.bus.lifeline import PARENT_ENV
from shared.errors import RecordingError
from shared.lifecycle import Closes
from shared.recording.rotation import numbered_parts, part_path

#: Longest wait for the recorder to be ready [s].
START_TIMEOUT = 30.0
#: What a stopping recorder needs beyond writing out its queue: closing the
#: file with its summary, then its Zenoh session [s].
CLOSE_MARGIN = 15.0
#: Longest wait for the recorder to exit after SIGTERM [s]: its own bound
#: for writing out its queue, and the margin (killed sooner, it would lose
#: a backlog it was allowed to write).
STOP_TIMEOUT = WRITE_OUT_TIMEOUT + CLOSE_MARGIN
#: Longest wait for a killed recorder to be reaped [s].
REAP_TIMEOUT = 15.0


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
    if options.rotation.keep_parts is not None:
        command += ["--keep-parts", str(options.rotation.keep_parts)]
    if not options.foxglove:
        command.append("--no-foxglove")
    command += [
        f"--planned-prefix={options.planned_prefix}",
        f"--executed-prefix={options.executed_prefix}",
        f"--commanded-prefix={options.commanded_prefix}",
    ]
    if options.overwrite:
        command.append("--overwrite")
    return command


class RecorderProcess(Closes):
    """A recorder running as its own process.

    Attributes:
        process: The OS process.
        options: What it records and where.
    """

    def __init__(
        self,
        process: subprocess.Popen[str],
        options: RecorderOptions,
        log_name: str | None = None,
    ):
        self.process = process
        self.options = options
        self._log_name = log_name
        self._lines: queue.Queue[str] = queue.Queue()  # its stdout, after ready
        self._failure = ""  # the reason it gave for exiting with an error

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
        options = replace(
            base,
            output=Path(output),
            keys=tuple(keys) if keys is not None else base.keys,
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
        name = getattr(log, "name", None)  # a file's path, for the errors
        recorder = cls(process, options, name if isinstance(name, str) else None)
        try:
            recorder._wait_ready(timeout)
        except BaseException:  # Ctrl-C, SIGTERM: no caller would ever stop it
            recorder.kill()
            raise
        return recorder

    def _wait_ready(self, timeout: float) -> None:
        stdout = self.process.stdout
        assert stdout is not None
        threading.Thread(
            target=_pump,
            args=(stdout, self._lines),
            name="recorder-stdout",
            daemon=True,
        ).start()
        try:
            line = self._lines.get(timeout=timeout)
        except queue.Empty:
            line = ""
        if not line.startswith(READY_PREFIX):
            self.kill()
            code = self.process.returncode
            raise RecordingError(
                f"the recorder for {self.options.output} did not start "
                f"(exit code {code}; {self._see_log()})",
                path=str(self.options.output),
            )

    def _see_log(self) -> str:
        """``"see its log"``, with the log's path if it is a named file."""
        return (
            "see its log" if self._log_name is None else f"see its log {self._log_name}"
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
        numbers = [_part_number(p) for p in numbered_parts(output)]
        first = numbers[0] if numbers else 1  # later with --keep-parts
        found, number = [], first
        while (path := part_path(output, number)).exists():
            found.append(path)
            number += 1
        return found

    def _open_file(self) -> Path:
        """The file being written when it ended: the last part if it rotates.

        (The earlier parts were finished whole; the output path itself,
        ``s.mcap``, is no file of a rotating recording: its parts are
        ``s-0001.mcap`` ...)
        """
        parts = self.paths if self.options.rotation.rotates else []
        return parts[-1] if parts else self.options.output

    def stop(self, timeout: float = STOP_TIMEOUT) -> list[Path]:
        """SIGTERM, wait for the files to be closed; the files written.

        Args:
            timeout: Longest wait for it to exit [s] (by default its own
                bound for writing out its queue, plus a margin).

        Raises:
            RecordingError: if it had to be killed (its files are readable up
                to the last flush, with ``recover``), or it exited with an
                error, now or earlier (the reason it gave, or how it died).
        """
        self._signal(signal.SIGTERM)
        try:
            self.process.wait(timeout)
        except subprocess.TimeoutExpired:
            self.kill()
            raise RecordingError(
                f"the recorder did not stop within {timeout:.0f} s and was killed; "
                f"{self._open_file()} is readable up to its last flush "
                "(armplan inspect --recover)",
                path=str(self.options.output),
            ) from None
        self._check_exit()
        return self.paths

    def _check_exit(self) -> None:
        """Raise if the recorder exited otherwise than with code 0.

        Raises:
            RecordingError: the exit code (or the signal that ended it), the
                reason it printed, and where its log is.
        """
        code = self.process.returncode
        if code == 0:
            return
        if code < 0:
            how = f"was killed by {_signal_name(-code)}"
        else:
            how = f"failed (exit code {code})"
        reason = self._reason()
        said = f": {reason}" if reason else f"; {self._open_file()} lacks its summary"
        raise RecordingError(
            f"the recorder of {self.options.output} {how}{said}; {self._see_log()}",
            path=str(self.options.output),
        )

    def _reason(self) -> str:
        """The last failure the recorder printed on stdout, or ``""``."""
        while True:
            try:
                line = self._lines.get(timeout=1.0)  # its stdout closes as it ends
            except queue.Empty:
                return self._failure
            if not line:  # end of its output
                self._lines.put(line)  # for a second stop
                return self._failure
            if line.startswith(FAILED_PREFIX):
                self._failure = line.removeprefix(FAILED_PREFIX)

    def kill(self) -> None:
        """SIGKILL (the files keep what was flushed) and reap it."""
        self._signal(signal.SIGKILL)
        with contextlib.suppress(subprocess.TimeoutExpired):
            self.process.wait(REAP_TIMEOUT)

    def _signal(self, signum: int) -> None:
        if self.process.poll() is None:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(self.process.pid, signum)

    def close(self) -> None:
        """Stop the recorder (what leaving the ``with`` does)."""
        self.stop()


def _part_number(path: Path) -> int:
    """The number of a numbered part: ``s-0003.mcap`` -> 3."""
    return int(path.stem.rsplit("-", 1)[1])


def _signal_name(signum: int) -> str:
    """``"SIGKILL"`` for 9, and so on (the number if it has no name)."""
    try:
        return signal.Signals(signum).name
    except ValueError:
        return f"signal {signum}"


def _pump(stream: IO[str], lines: queue.Queue[str]) -> None:
    """Copy ``stream``'s lines into ``lines`` until it closes."""
    for line in stream:
        lines.put(line.rstrip("\n"))
    lines.put("")
