"""A command whose output cannot be written says so in one line, exit 1."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

#: Commands that write to stdout, in-process and quick: the plan's JSON and
#: table, forward kinematics' JSON and table.
COMMANDS = {
    "plan-json": ["plan", "--target", "0.12", "-0.13", "0.05", "--json"],
    "plan-table": ["plan", "--target", "0.12", "-0.13", "0.05"],
    "fk-json": ["fk", "--joints", "0", "0", "0", "0.5", "0", "--json"],
    "fk-table": ["fk", "--joints", "0", "0", "0", "0.5", "0"],
}


def run(args: list[str], stdout: int | None) -> subprocess.CompletedProcess[str]:
    """``armplan args`` with ``stdout`` as its fd 1 (``None``: fd 1 closed)."""
    return subprocess.run(
        [sys.executable, "-m", "armplan", *args],
        stdout=stdout,
        stderr=subprocess.PIPE,
        text=True,
        timeout=120,
        check=False,
        preexec_fn=(lambda: os.close(1)) if stdout is None else None,
    )


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full")
@pytest.mark.parametrize("command", COMMANDS)
def test_a_full_disk_is_one_line_not_a_traceback(command: str) -> None:
    """`> /dev/full` ended in an OSError traceback (Errno 28)."""
    with open("/dev/full", "w") as full:
        done = run(COMMANDS[command], full.fileno())
    assert done.returncode == 1
    assert done.stderr == (
        "armplan: error: cannot write the output: No space left on device\n"
    )


@pytest.mark.parametrize("command", COMMANDS)
def test_a_closed_stdout_is_one_line_not_a_traceback(command: str) -> None:
    """`>&-` ended in AttributeError: 'NoneType' object has no attribute 'write'."""
    done = run(COMMANDS[command], None)
    assert done.returncode == 1
    assert done.stderr == "armplan: error: cannot write the output: stdout is closed\n"


def test_an_error_with_json_and_no_stdout_is_still_said_on_stderr() -> None:
    """The JSON error cannot be written either: stderr and exit 1 still say it."""
    done = run(["plan", "--target", "9", "9", "9", "--json"], None)
    assert done.returncode == 1
    assert done.stderr.startswith("armplan: error: target (9, 9, 9) m is ")
    assert "Traceback" not in done.stderr


def test_a_reader_that_left_still_ends_quietly() -> None:
    """`| head -1`: exit 0, nothing on stderr, as before."""
    process = subprocess.Popen(
        [sys.executable, "-m", "armplan", *COMMANDS["plan-json"]],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert process.stdout is not None and process.stderr is not None
    assert process.stdout.readline() == "{\n"
    process.stdout.close()
    assert process.wait(timeout=120) == 0
    assert process.stderr.read() == ""
    process.stderr.close()
