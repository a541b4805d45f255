"""``armplan decide --remote/--connect`` against the real decide and ik
services: the same output as in this process."""

from __future__ import annotations

import pathlib
import subprocess
from collections.abc import Iterator

import pytest
from test_cli_plan import GOAL, write_path

from armplan.cli.main import main
from armplan.launch import Launcher, free_endpoint
from shared.bus import load_config

CASES = {
    "target": ["--target", *map(str, GOAL)],
    "left-palm": [
        *["--arm", "left", "--target", "0.12", "0.10", "0.05"],
        *["--palm", "0", "-1", "0"],
    ],
    "start-duration": [
        *["--target", *map(str, GOAL), "--duration", "1.2"],
        *["--start", "1.0", "-0.2", "1.0", "0.5", "0.0"],
    ],
    "unreachable": ["--target", "0.5", "-0.12", "0.05"],  # the same error
}


@pytest.fixture(scope="module")
def endpoint() -> Iterator[str]:
    """A router and the decide and ik services on a free port."""
    config = load_config(endpoints=(free_endpoint(),))
    with Launcher(config, ["fit", "decide", "ik"], log=subprocess.DEVNULL):
        yield config.endpoint


def run(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    code = main(["decide", *args])
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.mark.parametrize("case", CASES.values(), ids=CASES.keys())
@pytest.mark.parametrize("json_flag", [["--json"], []], ids=["json", "table"])
def test_remote_output_is_the_in_process_output(
    capsys: pytest.CaptureFixture[str],
    endpoint: str,
    case: list[str],
    json_flag: list[str],
) -> None:
    """Same stdout, stderr and exit code, byte for byte (the table's wrist
    error at the end comes from the ik service's tracking)."""
    local = run(capsys, *case, *json_flag)
    remote = run(capsys, *case, *json_flag, "--remote", "--connect", endpoint)
    assert remote == local
    assert local[0] == (1 if case is CASES["unreachable"] else 0)


def test_a_wrist_path_remotely(
    capsys: pytest.CaptureFixture[str], endpoint: str, tmp_path: pathlib.Path
) -> None:
    file, _ = write_path(tmp_path)
    local = run(capsys, "--wrist-path", str(file))
    assert local[0] == 0 and "points; wrist" in local[1]
    assert run(capsys, "--wrist-path", str(file), "--connect", endpoint) == local


@pytest.mark.parametrize(
    ("options", "field"),
    [
        (["--grid"], "grid"),
        (["--target", "0.1", "-0.1", "0.0", "--model", "m.json"], "model"),
    ],
)
def test_what_runs_only_here_is_refused_with_remote(
    capsys: pytest.CaptureFixture[str], options: list[str], field: str
) -> None:
    """No service is asked: the options are refused first, naming the option."""
    code, _, err = run(capsys, *options, "--remote")
    assert code == 1
    assert f"--{field} does not go with --remote" in err
