"""``-o /dev/stdout``: the file written there holds what ``-o FILE`` writes, alone.

``armplan demos synth -o /dev/stdout > d.mcap`` printed its summary
("/dev/stdout: 1 subject, ...") to standard output as well, over the
MCAP's first bytes (its magic: the file was no MCAP), and ``armplan fit
-o /dev/stdout | next`` sent its tables after the model's JSON. The
summaries now go to standard error while the output is standard output
(``armplan.cli.output.apart_from``). Real processes; the files compared
byte for byte with those written by ``-o FILE``.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import IO

import pytest
from native_processes import ROOT

from shared.demos import read_demos

SYNTH = ["demos", "synth", "--subjects", "1", "--trials", "1"]


def armplan(
    *args: str, stdout: IO[bytes] | int = subprocess.PIPE
) -> subprocess.CompletedProcess[bytes]:
    """``python -m armplan ARGS``, its stdout as given, its stderr read."""
    return subprocess.run(
        [sys.executable, "-m", "armplan", *args],
        stdout=stdout,
        stderr=subprocess.PIPE,
        timeout=300,
        check=False,
        cwd=ROOT,
    )


@pytest.fixture(scope="module")
def demos(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A small synthetic demonstration set written with ``-o FILE``."""
    path = tmp_path_factory.mktemp("demos") / "d.mcap"
    done = armplan(*SYNTH, "-o", str(path))
    assert done.returncode == 0, done.stderr
    return path


def test_demos_written_to_a_redirected_stdout_are_the_file_alone(
    demos: Path, tmp_path: Path
) -> None:
    """Redirected to a file: the same bytes as ``-o FILE``; the summary on
    standard error."""
    redirected = tmp_path / "redirected.mcap"
    with redirected.open("wb") as out:
        done = armplan(*SYNTH, "-o", "/dev/stdout", stdout=out)
    assert done.returncode == 0, done.stderr
    assert redirected.read_bytes() == demos.read_bytes()
    assert done.stderr.decode().startswith("/dev/stdout: 1 subject, 16 trials")
    assert len(read_demos([redirected]).trials) == 16


def test_demos_written_into_a_pipe_are_the_file_alone(
    demos: Path, tmp_path: Path
) -> None:
    """Into a pipe (``-o /dev/stdout | ssh host 'cat > d.mcap'``): the same
    bytes as ``-o FILE``. The MCAP writer's seek failed there: the pipe got
    the file's first 39 bytes and the command exited 1, "cannot write
    /dev/stdout: Illegal seek"."""
    piped = armplan(*SYNTH, "-o", "/dev/stdout")
    assert piped.returncode == 0, piped.stderr
    assert piped.stdout == demos.read_bytes()
    assert piped.stderr.decode().startswith("/dev/stdout: 1 subject, 16 trials")


def test_a_model_fitted_into_a_pipe_is_the_model_alone(
    demos: Path, tmp_path: Path
) -> None:
    """Into a pipe: the model's bytes as ``-o FILE`` writes them, the tables
    on standard error."""
    direct = tmp_path / "model.json"
    done = armplan("fit", str(demos), "-o", str(direct))
    assert done.returncode == 0, done.stderr
    piped = armplan("fit", str(demos), "-o", "/dev/stdout")
    assert piped.returncode == 0, piped.stderr
    assert piped.stdout == direct.read_bytes()
    assert b"exponential densities" in piped.stderr
