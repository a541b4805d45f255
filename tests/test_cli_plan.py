"""armplan plan: the trajectory JSON contract, wrist paths, tasks, clear errors."""

from __future__ import annotations

import json
import os
import pathlib
import re
import subprocess
import sys
import threading

import numpy as np
import pytest

from armplan.cli.main import main
from armplan.demo.task import DEFAULT_TASK as DEMO_TASK
from services.planner.wrist_path import reach_path
from services.timing import check_limits
from shared.messages import Trajectory, parse
from shared.robot import load_arm, motion_limits
from shared.robot.postures import rest

GOAL = (0.12, -0.10, 0.05)
LEFT_GOAL = (0.12, 0.10, 0.05)
OTHER = (0.10, -0.14, 0.0)
#: GOAL and OTHER as command-line words.
AT_GOAL, AT_OTHER = [str(v) for v in GOAL], [str(v) for v in OTHER]
FIELDS = ["arm", "joint_names", "times", "positions", "velocities"]
FIELDS += ["accelerations", "primitives", "wrist_path", "method"]


def armplan(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "armplan", *args],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )


def plan_json(capsys: pytest.CaptureFixture[str], *args: str) -> Trajectory:
    assert main(["plan", *args, "--json"]) == 0
    return parse(Trajectory, capsys.readouterr().out)


def wrists(trajectory: Trajectory) -> np.ndarray:
    arm = load_arm(trajectory.arm)
    return np.array([arm.fk(np.array(q)).wrist for q in trajectory.positions])


def write_path(
    folder: pathlib.Path, duration: float = 1.0
) -> tuple[pathlib.Path, list[str]]:
    """A minimum-jerk reach to GOAL from the hanging right arm, as CSV; and
    its lines. Positions to 1 nm: rounded to 1 um, the curve the robot
    plays through the joints jerks at 1.3-1.4 times the limit where the
    wrist barely moves (docs/planning.md)."""
    path = reach_path(load_arm("right"), rest("right"), np.array(GOAL), duration)
    lines = ["t,x,y,z"] + [
        f"{t:.6f},{x:.9f},{y:.9f},{z:.9f}"
        for t, (x, y, z) in zip(path.times, path.positions, strict=True)
    ]
    file = folder / "path.csv"
    file.write_text("\n".join(lines) + "\n")
    return file, lines


def test_json_contract_in_a_real_process() -> None:
    """plan --target --json prints the SPEC's trajectory: one row per time,
    NAO joint names, 100 Hz, at rest at both ends, ending on the target."""
    out = armplan("plan", "--target", *AT_GOAL, "--json")
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    assert list(data) == FIELDS
    n = len(data["times"])
    assert data["arm"] == "right" and data["method"] == "mp"
    assert data["joint_names"] == list(load_arm("right").joint_names)
    for name in ("positions", "velocities", "accelerations"):
        assert np.array(data[name]).shape == (n, 5)
    assert len(data["primitives"]) == n and np.array(data["wrist_path"]).shape == (n, 3)
    np.testing.assert_allclose(np.diff(data["times"]), 0.01, atol=1e-12)
    assert np.allclose(data["velocities"][0], 0) and np.allclose(
        data["velocities"][-1], 0
    )
    trajectory = parse(Trajectory, data)
    assert np.linalg.norm(wrists(trajectory)[-1] - GOAL) < 1e-3


def test_dwell_belongs_to_the_target_before_it(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """Reach, hold 0.5 s, retreat: one trajectory at rest on the first target
    for the dwell; the same dwell after the second target holds there instead."""
    held = plan_json(
        capsys, "--target", *AT_GOAL, "--dwell", "0.5", "--target", *AT_OTHER
    )
    at_first = np.linalg.norm(wrists(held) - GOAL, axis=1) < 1e-3
    assert at_first.sum() * 0.01 >= 0.5
    assert np.linalg.norm(wrists(held)[-1] - OTHER) < 1e-3
    check_limits(held.times, held.positions, motion_limits(load_arm("right").limits))
    later = plan_json(
        capsys, "--target", *AT_GOAL, "--target", *AT_OTHER, "--dwell", "0.5"
    )
    at_first = np.linalg.norm(wrists(later) - GOAL, axis=1) < 1e-3
    at_second = np.linalg.norm(wrists(later) - OTHER, axis=1) < 1e-3
    assert at_first.sum() * 0.01 < 0.2 and at_second.sum() * 0.01 >= 0.5


def test_a_task_file_plans_what_the_options_plan(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--task FILE.json (a PlanRequest) gives the same trajectory as the same
    task on the command line; --method beside it overrides the file's."""
    task = {
        "arm": "right",
        "targets": [{"position": GOAL, "dwell": 0.3}, {"position": OTHER}],
    }
    file = tmp_path / "task.json"
    file.write_text(json.dumps(task))
    from_file = plan_json(capsys, "--task", str(file))
    options = ("--target", *AT_GOAL, "--dwell", "0.3", "--target")
    from_options = plan_json(capsys, *options, *AT_OTHER)
    assert from_file == from_options
    baseline = plan_json(capsys, "--task", str(file), "--method", "least-norm")
    assert baseline.method == "least-norm" and set(baseline.primitives) == {
        "least-norm"
    }


def test_a_task_file_with_a_byte_order_mark_is_read(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A task file saved by Windows Notepad starts with a byte-order mark; it
    was refused as "not valid JSON (... expected value at line 1 column 1)",
    where the file shows nothing wrong. It plans as the same file without
    one, as a wrist-path CSV with one does."""
    task = json.dumps({"targets": [{"position": GOAL}]})
    plain, marked = tmp_path / "plain.json", tmp_path / "marked.json"
    plain.write_text(task)
    marked.write_text(task, encoding="utf-8-sig")
    assert marked.read_bytes().startswith(b"\xef\xbb\xbf")
    assert plan_json(capsys, "--task", str(marked)) == plan_json(
        capsys, "--task", str(plain)
    )


@pytest.mark.parametrize(
    "text,key",
    [
        (
            '{"targets": [{"position": [0.12, -0.13, 0.05]}], '
            '"targets": [{"position": [0.14, -0.06, 0.10]}]}',
            "targets",
        ),
        (
            '{"targets": [{"position": [0.12, -0.13, 0.05], '
            '"dwell": 0.5, "dwell": 5}]}',
            "dwell",
        ),
    ],
    ids=["targets", "dwell"],
)
def test_a_task_file_with_a_key_written_twice_is_refused(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str], text: str, key: str
) -> None:
    """The second "targets" list was planned alone, the first dropped without
    a word (JSON parsers keep a repeated key's last value); a target with two
    dwells rested the last. Refused, naming the key, before any planning."""
    file = tmp_path / "task.json"
    file.write_text(text)
    assert main(["plan", "--task", str(file)]) == 1
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err == (
        f"armplan: error: {file}: PlanRequest: key {key!r} is written twice in "
        "one object; only the last would be read: keep one\n"
    )


def test_the_arm_of_a_task_file_in_any_case_or_from_the_option(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A task naming no arm (as the docs' example) was refused with --arm
    left ('the task is for the right arm'); --arm now gives its arm. A file
    writing "Left" was refused too; it reads as --arm reads it."""
    left = (GOAL[0], -GOAL[1], GOAL[2])
    file = tmp_path / "task.json"
    file.write_text(json.dumps({"targets": [{"position": left}]}))
    from_option = plan_json(capsys, "--task", str(file), "--arm", "left")
    assert from_option.arm == "left"
    file.write_text(json.dumps({"arm": "Left", "targets": [{"position": left}]}))
    assert plan_json(capsys, "--task", str(file)) == from_option
    assert main(["plan", "--task", str(file), "--arm", "right"]) == 1
    assert "--arm right but the task" in capsys.readouterr().err


def test_a_task_files_wrist_path_is_the_tasks_arm(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A left task whose wrist path named no arm was refused ('wrist_path is
    for the right arm, the request for the left'): the path takes the task's
    arm, from the file or from --arm, and reads "Left" as the task does. A
    path that names the other arm is still refused."""
    left = reach_path(load_arm("left"), rest("left"), np.array(LEFT_GOAL), 1.0)
    path = {"times": left.times.tolist(), "positions": left.positions.tolist()}
    file = tmp_path / "task.json"
    file.write_text(json.dumps({"arm": "left", "wrist_path": path}))
    planned = plan_json(capsys, "--task", str(file))
    assert planned.arm == "left" and planned.times == path["times"]
    file.write_text(json.dumps({"arm": "Left", "wrist_path": path | {"arm": "Left"}}))
    assert plan_json(capsys, "--task", str(file)) == planned
    file.write_text(json.dumps({"wrist_path": path}))
    assert plan_json(capsys, "--task", str(file), "--arm", "left") == planned
    file.write_text(json.dumps({"arm": "left", "wrist_path": path | {"arm": "right"}}))
    assert main(["plan", "--task", str(file)]) == 1
    assert "wrist_path is for the right arm, the request for the left" in (
        capsys.readouterr().err
    )


def test_a_task_naming_the_arm_on_its_wrist_path_only_is_for_that_arm(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """{"wrist_path": {"arm": "left", ...}} was refused as for the right arm
    (the default), even with --arm left: the request takes its path's arm,
    and --arm must agree with it."""
    left = reach_path(load_arm("left"), rest("left"), np.array(LEFT_GOAL), 1.0)
    path = {"times": left.times.tolist(), "positions": left.positions.tolist()}
    file = tmp_path / "task.json"
    file.write_text(json.dumps({"arm": "left", "wrist_path": path}))
    planned = plan_json(capsys, "--task", str(file))
    file.write_text(json.dumps({"wrist_path": path | {"arm": "left"}}))
    assert plan_json(capsys, "--task", str(file)) == planned
    assert plan_json(capsys, "--task", str(file), "--arm", "left") == planned
    assert main(["plan", "--task", str(file), "--arm", "right"]) == 1
    assert f"--arm right but the task {file} is for the left arm" in (
        capsys.readouterr().err
    )


def test_weights_beside_a_task_file_join_the_files_own(
    tmp_path: pathlib.Path,
) -> None:
    """--omega beside a task whose file sets mu: the request has both (the
    file's other weights stay), and the same weights written in the file
    give the same request."""
    import argparse

    from armplan.cli.commands.plan import add_parser
    from armplan.cli.plan_request import request_from_args

    parser = argparse.ArgumentParser()
    add_parser(parser.add_subparsers())
    target = {"position": GOAL, "palm": (0.0, 0.0, 1.0)}
    file = tmp_path / "task.json"
    file.write_text(json.dumps({"targets": [target], "measures": {"mu": 0.1}}))
    beside = request_from_args(
        parser.parse_args(["plan", "--task", str(file), "--omega", "0"])
    )
    assert (beside.measures.mu, beside.measures.omega) == (0.1, 0.0)
    both = tmp_path / "both.json"
    both.write_text(
        json.dumps({"targets": [target], "measures": {"mu": 0.1, "omega": 0.0}})
    )
    assert request_from_args(parser.parse_args(["plan", "--task", str(both)])) == (
        beside
    )


def test_fastest_rate_and_left_arm(capsys: pytest.CaptureFixture[str]) -> None:
    """--fastest is quicker than human pace; --rate sets the sample interval;
    --arm left plans the left arm with its joint names."""
    goal = ("0.12", "0.10", "0.05")
    human = plan_json(capsys, "--arm", "left", "--target", *goal)
    fastest = plan_json(capsys, "--arm", "left", "--target", *goal, "--fastest")
    assert fastest.duration < human.duration
    assert human.joint_names[0] == "LShoulderPitch"
    slow = plan_json(capsys, "--arm", "left", "--target", *goal, "--rate", "50")
    np.testing.assert_allclose(np.diff(slow.times), 0.02, atol=1e-12)


@pytest.mark.parametrize("method", ["mp", "least-norm"])
def test_a_wrist_path_keeps_its_times(
    method: str, tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--wrist-path: the output times are the CSV's, exactly; the hand is on
    the path (within 1 mm) at every sample."""
    file, lines = write_path(tmp_path)
    trajectory = plan_json(capsys, "--wrist-path", str(file), "--method", method)
    rows = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    assert trajectory.times == rows[:, 0].tolist()
    assert np.linalg.norm(wrists(trajectory) - rows[:, 1:], axis=1).max() < 1e-3
    assert trajectory.method == method


def test_a_wrist_path_with_a_byte_order_mark_is_read(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A CSV saved as Excel's "CSV UTF-8" starts with a byte-order mark; it
    was refused as lacking its t,x,y,z header. It plans as the same file
    without one."""
    file, lines = write_path(tmp_path)
    marked = tmp_path / "marked.csv"
    marked.write_text("\n".join(lines) + "\n", encoding="utf-8-sig")
    assert marked.read_bytes().startswith(b"\xef\xbb\xbf")
    with_mark = plan_json(capsys, "--wrist-path", str(marked))
    without = plan_json(capsys, "--wrist-path", str(file))
    assert with_mark.positions == without.positions


def test_the_table_and_summary(capsys: pytest.CaptureFixture[str]) -> None:
    """Without --json: every tenth sample in degrees with its primitive, then
    duration, primitives in order, final wrist error [mm] and method."""
    trajectory = plan_json(capsys, "--target", *AT_GOAL)
    assert main(["plan", "--target", *AT_GOAL]) == 0
    text = capsys.readouterr().out
    table, summary = text.split("\n\n")
    rows = table.splitlines()[1:]
    n = len(trajectory.times)
    assert len(rows) == len({*range(0, n, 10), n - 1})
    last = rows[-1].split()
    assert float(last[0]) == pytest.approx(trajectory.times[-1])
    np.testing.assert_allclose(
        [float(v) for v in last[1:6]],
        np.degrees(trajectory.positions[-1]),
        atol=0.006,
    )
    assert f"duration {trajectory.duration:.3f} s" in summary
    assert "method mp" in summary and "human pace" in summary
    order = summary.split("primitives in order: ")[1].splitlines()[0].split(" -> ")
    assert (
        order[0] == trajectory.primitives[0] and order[-1] == trajectory.primitives[-1]
    )
    error = re.search(r"final wrist error ([\d.]+) mm", summary)
    assert error is not None and float(error[1]) < 1.0


def test_a_plan_with_nothing_to_move_is_one_sample(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """A target where the arm already is gives one sample (the arm stays,
    docs/planning.md); the summary said "1 samples"."""
    arm = load_arm("right")
    here = [str(float(v)) for v in arm.fk(rest("right")).wrist]
    assert main(["plan", "--target", *here]) == 0
    assert "duration 0.000 s, 1 sample (100 Hz" in capsys.readouterr().out


def test_the_end_posture_line_is_the_next_plans_start(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """The table is in degrees and --start takes radians: a user chaining
    plans pasted the last row and was refused (39.31 rad), or, near zero,
    started 57 times off. The summary now prints the last posture in
    radians, each angle in full; given to --start, the next plan starts
    exactly there (with six decimals it started up to 5e-7 rad away)."""
    first = plan_json(capsys, "--target", *AT_GOAL)
    assert main(["plan", "--target", *AT_GOAL]) == 0
    line = re.search(r"end posture \[rad\] \(the next plan's --start\): (.+)",
                     capsys.readouterr().out)  # fmt: skip
    assert line is not None
    words = line[1].split()
    assert [float(w) for w in words] == list(first.positions[-1])
    second = plan_json(capsys, "--target", *AT_OTHER, "--start", *words)
    assert list(second.positions[0]) == list(first.positions[-1])


def test_a_coarse_rate_says_it_lengthens_the_reach(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """At 16 Hz a 0.7 s reach lasts 0.75 s, twelve whole periods: the
    summary says why it is slower than human pace; at 100 Hz it says human
    pace alone."""
    assert main(["plan", "--target", *AT_GOAL, "--rate", "16"]) == 0
    coarse = capsys.readouterr().out.split("\n\n")[1]
    assert "duration 0.750 s, 13 samples (16 Hz, human pace, each reach " in coarse
    assert "lengthened to whole 0.0625 s samples)" in coarse
    assert main(["plan", "--target", *AT_GOAL]) == 0
    assert "(100 Hz, human pace); method" in capsys.readouterr().out


def _bad_paths(folder: pathlib.Path) -> dict[str, tuple[pathlib.Path, str]]:
    """Each bad wrist-path file and what its error must say."""
    _, lines = write_path(folder)
    header = "t,x,y,z\n"
    texts = {
        "header": ("time,x,y,z\n0,0.1,-0.1,0\n", "header t,x,y,z"),
        "word": (header + "0,0.1,-0.1,0\n0.1,0.1,abc,0\n", "line 3"),
        "nan": (header + "0,0.1,-0.1,0\n0.1,nan,-0.1,0\n", "line 3: x = nan"),
        "inf": (header + "0,0.1,-0.1,0\ninf,0.1,-0.1,0\n", "line 3: t = inf"),
        "empty": (header, "the wrist path is empty"),
        "one": (
            header + "0,0.12,-0.13,0.05\n",
            f"a wrist path needs at least 2 samples, {folder / 'one.csv'} has 1",
        ),
        "order": (header + "0,0.1,-0.1,0\n0.2,0.1,-0.1,0\n0.2,0.1,-0.1,0\n", "line 4"),
        "blank": (
            header + "\n0,0.1,-0.1,0\n\n0.2,0.1,-0.1,0\n\n0.2,0.1,-0.1,0\n",
            "line 7: times must increase: t = 0.2 s is not after t = 0.2 s on line 5",
        ),
    }
    out = {"missing": (folder / "missing.csv", "missing.csv: cannot read")}
    for name, (text, message) in texts.items():
        (folder / f"{name}.csv").write_text(text)
        out[name] = (folder / f"{name}.csv", message)
    lines[41] = "0.400000,0.3,-0.1,0.1"  # sample 40 far out of reach
    (folder / "reach.csv").write_text("\n".join(lines) + "\n")
    out["reach"] = (folder / "reach.csv", "wrist-path sample 40 (t = 0.400 s)")
    return out


@pytest.mark.parametrize(
    "case",
    [
        "missing",
        "header",
        "word",
        "nan",
        "inf",
        "empty",
        "one",
        "order",
        "blank",
        "reach",
    ],
)
def test_a_bad_wrist_path_is_a_clear_error(
    case: str, tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Missing file, wrong header, a non-number, NaN, inf, no samples, one
    sample (it was planned as a 0 s trajectory), times not increasing, a
    sample out of reach: exit 1 and an error naming the line or sample (and
    the JSON error with --json). Lines are the file's, blank ones counted."""
    file, message = _bad_paths(tmp_path)[case]
    assert main(["plan", "--wrist-path", str(file), "--json"]) == 1
    captured = capsys.readouterr()
    assert message in captured.err and "Traceback" not in captured.err
    assert message in json.loads(captured.out)["error"]["message"]


def test_too_fast_names_the_joint_and_sample(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A reach squeezed into 80 ms breaks a speed limit: the joint, the
    sample and its time are named."""
    file, _ = write_path(tmp_path, 0.08)
    assert main(["plan", "--wrist-path", str(file)]) == 1
    err = capsys.readouterr().err
    assert re.search(r"R\w+ velocity .* at sample \d+ \(t = 0\.\d+ s\) exceeds", err)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--dwell", "0.5", "--target", *GOAL], "--dwell comes before any --target"),
        (
            ["--target", *GOAL, "--dwell", "1", "--dwell", "2"],
            "--target number 1 has --dwell twice",
        ),
        (["--target", "0.12", "nan", "0.05"], "--target number 1 (0.12 nan 0.05)"),
        (
            ["--target", *GOAL, "--target", *OTHER, "--dwell", "61"],
            "--dwell of --target number 2",
        ),
        (["--target", *GOAL, "--palm", "0", "0", "0"], "zero vector"),
        (["--target", "0.5", "-0.1", "0.05"], "m from the right shoulder"),
        (["--target", *GOAL, "--rate", "0"], "rate"),
        (["--target", *GOAL, "--rate", "1e-300"], "rate: 1e-300 Hz is below the 16"),
        (["--target", *GOAL, "--rate", "15.9"], "rate: 15.9 Hz is below the 16 Hz"),
        (["--target", "1e308", "0", "0"], "is 1e+308 m from the right shoulder;"),
        (
            ["--target", *GOAL, "--start", "1e308", "0", "0", "0", "0"],
            "RShoulderPitch = 1e+308 rad in the start posture",
        ),
        (["--target", *GOAL, "--arm", "middle"], "unknown arm 'middle'"),
        (["--target", *GOAL, "--start", "9", "0", "0", "0", "0"], "RShoulderPitch"),
        (["--task", "no-such-task.json"], "no-such-task.json: cannot read the task"),
        (
            ["--task", str(DEMO_TASK)],
            "it is a demo task, for `armplan demo --task FILE`",
        ),
    ],
)
def test_bad_options_are_clear_errors(
    args: list[str], message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """Misplaced or repeated per-target options, non-finite or out-of-range
    values, unreachable targets, bad starts: exit 1 and the problem named."""
    assert main(["plan", *map(str, args)]) == 1
    assert message in capsys.readouterr().err


def test_a_task_nested_too_deeply_is_a_clear_error(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """100 000 nested lists: "not valid JSON", as `demo --task` says; the
    demo task hint read the file again and its RecursionError escaped."""
    path = tmp_path / "deep.json"
    path.write_text("[" * 100_000 + "]" * 100_000)
    assert main(["plan", "--task", str(path)]) == 1
    err = capsys.readouterr().err
    assert "not valid JSON" in err and "Traceback" not in err


def test_options_that_do_not_apply_to_a_wrist_path(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--fastest, --rate and --dwell with --wrist-path are refused by name
    (its own times are kept); a bad task file names its field."""
    file, _ = write_path(tmp_path)
    for extra in (["--fastest"], ["--rate", "50"], ["--dwell", "1"]):
        assert main(["plan", "--wrist-path", str(file), *extra]) == 1
        assert f"{extra[0]} " in capsys.readouterr().err
    task = tmp_path / "task.json"
    task.write_text(json.dumps({"targets": [{"position": GOAL, "dwell": -1}]}))
    assert main(["plan", "--task", str(task)]) == 1
    assert "targets.0.dwell" in capsys.readouterr().err


def test_a_task_that_is_no_regular_file_is_read_up_to_the_limit(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A named pipe (st_size 0) passed the task's size check and was read
    whole: `--task /dev/zero` took 15 GB in 20 s. It is refused once it has
    given more than MAX_TASK_BYTES."""
    from armplan.cli.plan_request import MAX_TASK_BYTES

    fifo = tmp_path / "task.json"
    os.mkfifo(fifo)
    writer = threading.Thread(target=_feed, args=(fifo, MAX_TASK_BYTES + 4096))
    writer.start()
    try:
        assert main(["plan", "--task", str(fifo)]) == 1
    finally:
        writer.join()
    error = capsys.readouterr().err
    assert f"cannot read the task (more than {MAX_TASK_BYTES} bytes)" in error


def _feed(fifo: pathlib.Path, size: int) -> None:
    """Write ``size`` bytes of spaces into ``fifo``, up to the reader's leaving."""
    try:
        with open(fifo, "wb") as stream:
            for _ in range(0, size, 65536):
                stream.write(b" " * 65536)
    except BrokenPipeError:
        pass


def test_a_pace_or_rate_for_a_tasks_wrist_path_is_refused(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """`--task` with a wrist path ignored --rate and --fastest beside it and
    "rate" and "fastest" in it (a 50 Hz path asked at 10 Hz gave 50 Hz
    samples), where --wrist-path refuses them: refused alike, by name (at a
    rate the planner takes for targets)."""
    _, lines = write_path(tmp_path)
    times = [float(line.split(",")[0]) for line in lines[1:]]
    positions = [[float(v) for v in line.split(",")[1:]] for line in lines[1:]]
    task = tmp_path / "task.json"
    path = {"times": times, "positions": positions}
    task.write_text(json.dumps({"wrist_path": path}))
    for extra in (["--fastest"], ["--rate", "50"]):
        assert main(["plan", "--task", str(task), *extra]) == 1
        error = capsys.readouterr().err
        assert f"{extra[0]} does not apply to the wrist_path of the task" in error
    for pace in ({"rate": 50}, {"fastest": False}):
        task.write_text(json.dumps({"wrist_path": path} | pace))
        assert main(["plan", "--task", str(task)]) == 1
        error = capsys.readouterr().err
        assert next(iter(pace)) in error and "own times" in error
