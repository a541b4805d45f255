"""``armplan plan --remote/--connect`` against the real services: same output."""

from __future__ import annotations

import json
import os
import pathlib
import signal
import subprocess
import threading
from collections.abc import Iterator

import pytest
from test_cli_plan import AT_GOAL, AT_OTHER, write_path

from armplan.cli.main import main
from armplan.launch import Launcher, free_endpoint
from shared.bus import load_config

CASES = {
    "target": ["--target", *AT_GOAL],
    "left-least-norm": [
        *["--arm", "left", "--target", "0.12", "0.10", "0.05"],
        *["--method", "least-norm"],
    ],
    "dwell-palm-two": [
        *["--target", *AT_GOAL, "--dwell", "0.3", "--palm", "0", "0", "-1"],
        *["--target", *AT_OTHER, "--rate", "50"],
    ],
    "fastest-single": ["--target", *AT_GOAL, "--fastest", "--method", "single"],
    "unreachable": ["--target", "0.5", "-0.12", "0.05"],  # the same error
    # the limits reach the timing service
    "limits": [
        *["--target", *AT_GOAL, "--fastest"],
        *["--max-acceleration", "5", "--max-jerk", "40", "30", "30", "30", "30"],
    ],
    "limits-over-the-net": ["--target", *AT_GOAL, "--max-jerk", "1e9"],
}


@pytest.fixture(scope="module")
def stack() -> Iterator[Launcher]:
    """A router and the planner's services on a free port."""
    config = load_config(endpoints=(free_endpoint(),))
    names = ["decide", "ik", "timing", "planner"]
    with Launcher(config, names, log=subprocess.DEVNULL) as launched:
        yield launched


@pytest.fixture(scope="module")
def endpoint(stack: Launcher) -> str:
    """The router's endpoint of ``stack``."""
    return stack.config.endpoint


def run(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    code = main(["plan", *args])
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
    """Same stdout, stderr and exit code, byte for byte, with and without --remote."""
    local = run(capsys, *case, *json_flag)
    remote = run(capsys, *case, *json_flag, "--remote", "--connect", endpoint)
    assert remote == local


def test_a_wrist_path_file_plans_the_same_remotely(
    capsys: pytest.CaptureFixture[str], endpoint: str, tmp_path: pathlib.Path
) -> None:
    """--wrist-path: the planner keeps the CSV's times, as in-process."""
    file, _ = write_path(tmp_path)
    local = run(capsys, "--wrist-path", str(file), "--json")
    assert local[0] == 0
    assert run(capsys, "--wrist-path", str(file), "--json", "--connect", endpoint) == (
        local
    )


def test_no_planner_names_it(capsys: pytest.CaptureFixture[str]) -> None:
    """A router without the services: exit 1 naming 'planner' and its key."""
    config = load_config(endpoints=(free_endpoint(),))
    with Launcher(config, [], log=subprocess.DEVNULL):
        code, _, err = run(capsys, "--target", *AT_GOAL, "--connect", config.endpoint)
    assert code == 1
    assert "service 'planner' is unavailable for armplan/plan" in err


def test_a_task_file_with_an_old_request_id_is_planned_anew(
    capsys: pytest.CaptureFixture[str], endpoint: str, tmp_path: pathlib.Path
) -> None:
    """A request copied from a recording keeps its request_id: run twice,
    then edited, it is planned each time (not the first run's kept answer,
    nor refused as an id reused for another task)."""
    task = tmp_path / "request.json"
    request = {"targets": [{"position": [float(v) for v in AT_GOAL]}]}
    task.write_text(json.dumps(request | {"request_id": "from-a-recording"}))
    first = run(capsys, "--task", str(task), "--json", "--connect", endpoint)
    again = run(capsys, "--task", str(task), "--json", "--connect", endpoint)
    assert first[0] == again[0] == 0 and again == first
    request["targets"][0]["dwell"] = 0.5
    task.write_text(json.dumps(request | {"request_id": "from-a-recording"}))
    edited = run(capsys, "--task", str(task), "--json", "--connect", endpoint)
    assert edited[0] == 0, edited[2]
    assert json.loads(edited[1])["times"][-1] > json.loads(first[1])["times"][-1]


def test_timeout_sets_the_wait_and_a_timeout_says_to_give_a_longer_one(
    capsys: pytest.CaptureFixture[str], stack: Launcher
) -> None:
    """A 64-target task at 1000 Hz, asked by four clients at once, outlasted
    the config's 5 s wait, with no option to wait longer ("service 'planner'
    did not answer armplan/plan within 5.000 s"). --timeout sets the wait:
    with the planner paused (SIGSTOP), a 1 s wait ends in request_timeout
    telling to give a longer one; running, a minute plans as without it."""
    where = ["--connect", stack.config.endpoint]
    planner = stack.services["planner"].process.pid
    os.kill(planner, signal.SIGSTOP)
    try:
        code, out, err = run(capsys, "--target", *AT_GOAL, *where, "--timeout", "1")
    finally:
        os.kill(planner, signal.SIGCONT)
    assert (code, out) == (1, "")
    assert err == (
        "armplan: error: service 'planner' did not answer armplan/plan within "
        "1.000 s; a long task or a busy planner takes longer: give a longer "
        "--timeout (this call waited 1 s)\n"
    )
    waited = run(capsys, "--target", *AT_GOAL, "--json", *where, "--timeout", "60")
    assert waited == run(capsys, "--target", *AT_GOAL, "--json", *where)
    assert waited[0] == 0


def test_a_stage_that_times_out_is_not_told_to_give_a_longer_timeout(
    capsys: pytest.CaptureFixture[str], stack: Launcher
) -> None:
    """A paused timing service ended a plan with "service 'timing' did not
    answer ...; give a longer --timeout (this call waited 20 s)", which a
    longer one does not change. Only the planner's own timeout says so."""
    where = ["--connect", stack.config.endpoint]
    timing = stack.services["timing"].process.pid
    os.kill(timing, signal.SIGSTOP)
    try:
        code, out, err = run(capsys, "--target", *AT_GOAL, *where, "--timeout", "2")
    finally:
        os.kill(timing, signal.SIGCONT)
    assert (code, out) == (1, "")
    assert "service 'timing' did not answer" in err
    assert "--timeout" not in err


def test_a_stage_slower_than_the_configs_timeout_is_waited_for(
    capsys: pytest.CaptureFixture[str], stack: Launcher
) -> None:
    """The planner gave each stage at most the configuration's 5 s, whatever
    its caller waited: with timing held up 7 s, a --timeout 30 plan failed
    at 5 s ("service 'timing' did not answer"). Now the stage waits what
    the caller has left, and the plan is the one asked without a pause.
    Held 6 s (it was 7): well inside Zenoh's 10 s lease, after which a
    frozen service is taken for dead and its query ends unanswered."""
    where = ["--connect", stack.config.endpoint]
    timing = stack.services["timing"].process.pid
    os.kill(timing, signal.SIGSTOP)
    resume = threading.Timer(6.0, os.kill, (timing, signal.SIGCONT))
    resume.start()
    try:
        held = run(capsys, "--target", *AT_GOAL, "--json", *where, "--timeout", "30")
    finally:
        resume.join()
        os.kill(timing, signal.SIGCONT)
    assert held[0] == 0, held[2]
    assert held == run(capsys, "--target", *AT_GOAL, "--json", *where)


@pytest.mark.parametrize(
    "args,words",
    [
        (["--timeout", "5"], "--timeout goes with --remote"),
        (["--remote", "--timeout", "nan"], "got nan"),
        (["--remote", "--timeout", "-1"], "got -1"),
        (["--remote", "--timeout", "0"], "got 0"),
    ],
    ids=["in-process", "nan", "negative", "zero"],
)
def test_a_timeout_that_is_no_wait_is_refused_before_connecting(
    capsys: pytest.CaptureFixture[str], args: list[str], words: str
) -> None:
    """No router runs here: refused before anything connects, naming it."""
    code, out, err = run(capsys, "--target", *AT_GOAL, *args)
    assert (code, out) == (1, "")
    assert words in err and "Traceback" not in err


@pytest.mark.parametrize(
    "args",
    [
        ["fit", "--remote", "--timeout", "nan", "demos.mcap"],
        ["plan", "--remote", "--timeout", "-1", "--target", *AT_GOAL],
        ["plan", "--timeout", "5", "--target", *AT_GOAL],
    ],
    ids=["fit", "plan", "plan-in-process"],
)
def test_a_refused_timeout_names_the_field_timeout(
    capsys: pytest.CaptureFixture[str], args: list[str]
) -> None:
    """fit's refusal named the field ``timeout`` until the check moved to
    ``armplan.cli.remote``, which said ``--timeout``; plan's "goes with
    --remote" said ``timeout``: one option, one field name."""
    assert main([*args, "--json"]) == 1
    error = json.loads(capsys.readouterr().out)["error"]
    assert error["evidence"]["field"] == "timeout"
